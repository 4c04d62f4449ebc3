"""Documents seen from outside: "Object.Property" paths to set and read, the output
properties, validity, the results and their export. Shared by run, sweep and solve."""
import math
import os

from ..geometry.errors import DeformError
from .env import load_freecad

App = load_freecad()

EXPORTS = ("step", "brep", "stl", "ply", "fcstd")


class BatchError(DeformError):
    """Bad batch input (a path, a range, a table): one sentence naming what to change."""


def split_path(path):
    """"Object.Property.sub" -> ("Object", ["Property", "sub"])."""
    head, _, rest = str(path).strip().partition(".")
    if not head or not rest:
        raise BatchError(f"{path!r} is not of the form Object.Property; name the object and "
                         f"its property with a dot between them.")
    return head, rest.split(".")


def open_document(path):
    """App.openDocument, refusing a missing file and a document whose Python objects did
    not load (they would not recompute, and stale results would pass for new ones)."""
    if not os.path.isfile(path):
        raise BatchError(f"{path} does not exist; give the path of a .FCStd document.")
    doc = App.openDocument(os.path.abspath(path))
    dead = [o.Name for o in doc.Objects if hasattr(o, "Proxy") and o.Proxy is None]
    if dead:
        App.closeDocument(doc.Name)
        raise BatchError(f"the Python code of {', '.join(dead)} did not load (its add-on "
                         f"is not importable here); install the add-on or put it on "
                         f"PYTHONPATH.")
    return doc


def find_object(doc, name):
    """The object called `name` (its internal Name, or else its Label)."""
    obj = doc.getObject(name)
    if obj is None:
        matches = doc.getObjectsByLabel(name)
        obj = matches[0] if matches else None
    if obj is None:
        raise BatchError(f"the document has no object {name!r}; use one of "
                         f"{', '.join(o.Name for o in doc.Objects)}.")
    return obj


def _number(text):
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(text)
    return value


def parse_value(obj, prop, text):
    """The value that `text` (a table cell) stands for, in the type of `obj.prop`: numbers
    become floats (ints, bools), anything else is given as is (a quantity such as "2.5 cm",
    an enumeration)."""
    if not isinstance(text, str):
        return text
    kind = obj.getTypeIdOfProperty(prop)
    text = text.strip()
    if kind == "App::PropertyBool":
        return text.lower() in ("1", "true", "yes", "on")
    if kind.startswith("App::PropertyInteger"):
        return int(float(text))
    if kind in ("App::PropertyString", "App::PropertyEnumeration"):
        return text
    if kind == "App::PropertyVector":
        return App.Vector(*(float(v) for v in text.strip("()[]").replace(",", " ").split()))
    try:
        return float(text)
    except ValueError:
        return text


def _with(value, attrs, new):
    """`value` with the attribute chain `attrs` set to `new` (FreeCAD hands out copies of a
    Placement's Base or Rotation, so each level is set back into its parent)."""
    if not attrs:
        return new
    child = _with(getattr(value, attrs[0]), attrs[1:], new)
    setattr(value, attrs[0], child)
    return value


def set_value(doc, path, text):
    """Set "Object.Property" (or a part of it: "Stretch.Plane.Base.x") from a table cell."""
    name, attrs = split_path(path)
    obj = find_object(doc, name)
    prop = attrs[0]
    if prop not in obj.PropertiesList:
        raise BatchError(f"{name} has no property {prop!r}; check the column {path!r}.")
    try:
        if len(attrs) == 1:
            setattr(obj, prop, parse_value(obj, prop, text))
        else:
            setattr(obj, prop, _with(getattr(obj, prop), attrs[1:], _number(text)))
    # FreeCAD: a ParserError (a RuntimeError) for "abc", an ArithmeticError for "3 kg"
    except (ValueError, TypeError, AttributeError, RuntimeError, ArithmeticError) as e:
        raise BatchError(f"{path} cannot take {text!r} ({_reason(e)}); give a value of its "
                         f"kind (a number, or a quantity in its unit).") from None


def _reason(error):
    """FreeCAD's exceptions carry a dict: its message alone."""
    first = error.args[0] if error.args else ""
    return first.get("sErrMsg", str(first)) if isinstance(first, dict) else str(error)


def plain(value):
    """A property value as a number, bool, string, tuple or list (quantities in their
    internal unit: mm, degrees)."""
    if isinstance(value, (bool, int, float, str)):
        return value
    if hasattr(value, "Value") and hasattr(value, "Unit"):
        return float(value.Value)
    if isinstance(value, App.Vector):
        return (value.x, value.y, value.z)
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return str(value)


def read_value(doc, path):
    """The value at "Object.Attribute.Attribute..." (e.g. "Stretch.VolumeChange",
    "Stretch.Shape.BoundBox.XLength", "Stretch.Shape.Face3.CenterOfMass.x")."""
    name, attrs = split_path(path)
    value = find_object(doc, name)
    for attr in attrs:
        try:
            value = getattr(value, attr)
        except AttributeError:
            raise BatchError(f"{path!r} does not exist: {attr!r} is unknown there.") from None
    return plain(value)


def text(value):
    """A table cell: floats written so they read back to the same bits."""
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return ";".join(text(v) for v in value)
    return str(value)


def output_names(doc):
    """Every output property (read-only results) as "Object.Output", in document order."""
    return [f"{obj.Name}.{prop}" for obj in doc.Objects for prop in obj.PropertiesList
            if {"Output", "ReadOnly"} <= set(obj.getTypeOfProperty(prop))
            and "Hidden" not in obj.getTypeOfProperty(prop)]


def results(doc):
    """The objects to export: Deform features nothing else uses (the ends of each chain);
    without any, every shape, mesh or cloud nothing else uses."""
    def data(obj):
        return any(hasattr(obj, p) for p in ("Shape", "Mesh", "Points"))
    tips = [o for o in doc.Objects if data(o) and not o.InList]
    deform = [o for o in tips if hasattr(getattr(o, "Proxy", None), "PROPERTIES")]
    return deform or tips


def status(doc):
    """(valid, error): valid when every object recomputed without error and every result
    shape passes OCCT's check; error is the first object's message."""
    for obj in doc.Objects:
        if "Invalid" in obj.State or "Error" in obj.State:
            message = obj.getStatusString() if hasattr(obj, "getStatusString") else "error"
            return False, f"{obj.Name}: {message}"
    for obj in results(doc):
        shape = getattr(obj, "Shape", None)
        if hasattr(obj, "Mesh") or hasattr(obj, "Points"):
            continue
        if shape is None or shape.isNull() or not shape.isValid():
            return False, f"{obj.Name}: the result is not a valid shape (OCCT check)."
    return True, ""


def _write_ply(points, path):
    with open(path, "w") as f:
        f.write(f"ply\nformat ascii 1.0\nelement vertex {len(points)}\n"
                "property double x\nproperty double y\nproperty double z\nend_header\n")
        f.writelines(f"{p.x!r} {p.y!r} {p.z!r}\n" for p in points)


def _mesh_of(shape):
    import Mesh
    box = shape.BoundBox
    return Mesh.Mesh(shape.tessellate(max(box.DiagonalLength * 1e-3, 1e-6)))


def export(doc, formats, folder, stem):
    """Write each result in each format as folder/stem_Object.ext (the document as
    folder/stem.FCStd); returns the file names written. A format that does not fit a
    result (STEP of a mesh) is left out."""
    os.makedirs(folder, exist_ok=True)
    written = []
    for fmt in formats:
        if fmt == "fcstd":
            doc.saveCopy(os.path.join(folder, f"{stem}.FCStd"))
            written.append(f"{stem}.FCStd")
            continue
        for obj in results(doc):
            name = f"{stem}_{obj.Name}.{fmt}"
            path = os.path.join(folder, name)
            if hasattr(obj, "Mesh"):
                if fmt not in ("stl", "ply"):
                    continue
                obj.Mesh.write(path)
            elif hasattr(obj, "Points"):
                if fmt != "ply":
                    continue
                _write_ply(obj.Points.Points, path)
            elif fmt == "step":
                obj.Shape.exportStep(path)
            elif fmt == "brep":
                obj.Shape.exportBrep(path)
            else:
                _mesh_of(obj.Shape).write(path)
            written.append(name)
    return written


def formats_of(spec):
    """"step,stl" -> ["step", "stl"]; an unknown format names --export."""
    formats = [f.strip().lower() for f in (spec or "").split(",") if f.strip()]
    unknown = [f for f in formats if f not in EXPORTS]
    if unknown:
        raise BatchError(f"--export {', '.join(unknown)} is not known; use some of "
                         f"{','.join(EXPORTS)}.")
    return formats
