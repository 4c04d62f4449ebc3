"""What every Deform feature shares: its properties, saving, the base it reads, its errors."""
import contextlib
import functools
import math
import sys
from typing import Any, NamedTuple

from ..geometry.errors import DeformError

OUTPUT = 1 | 8  # Prop_ReadOnly | Prop_Output: shown greyed out, setting it does not touch the object

KIND_WORDS = {"Part": "shape", "Mesh": "mesh", "Points": "point cloud"}
RESULT_TYPES = {"Part": "Part::FeaturePython", "Mesh": "Mesh::FeaturePython",
                "Points": "Points::FeaturePython"}


class Prop(NamedTuple):
    type: str
    name: str
    group: str
    doc: str
    default: Any = None
    output: bool = False
    unit: str = ""  # an App::PropertyQuantity's unit ("deg"): a quantity without bounds


def base_kind(base):
    """"Mesh", "Points" or "Part": which kind of data `base` carries (and the result will)."""
    if base is None:
        raise DeformError("Base is empty; link a solid, a mesh or a point cloud.", "Base")
    if base.isDerivedFrom("Mesh::Feature"):
        kind, empty = "Mesh", base.Mesh.CountPoints == 0
    elif base.isDerivedFrom("Points::Feature"):
        kind, empty = "Points", base.Points.CountPoints == 0
    elif hasattr(base, "Shape"):
        kind, empty = "Part", base.Shape.isNull()
    elif base.isDerivedFrom("Fem::FemMeshObject"):
        raise DeformError(f"Base {base.Label} is a FEM mesh, which only DimensionDrive "
                          f"deforms; link a solid, a mesh or a point cloud, or make a "
                          f"DimensionDrive on {base.Label}.", "Base")
    else:
        raise DeformError(f"Base {base.Label} is not a solid, a mesh or a point cloud; link "
                          f"one.", "Base")
    if empty:
        raise DeformError(f"Base {base.Label} is empty (nothing to deform); link a Base that "
                          f"holds a shape, a mesh or points.", "Base")
    return kind


def check_links(obj):
    """Base must not be the object itself nor depend on it: each recompute would deform
    the previous result again."""
    base = obj.Base
    if base is None:
        return
    try:
        cycle = base == obj or obj in base.OutListRecursive
    except IndexError:  # FreeCAD: "cyclic dependency detected"
        cycle = True
    if cycle:
        raise DeformError(f"Base {base.Label} depends on {obj.Label} itself, so every "
                          f"recompute would deform its own result again; link a Base that "
                          f"does not use {obj.Label}.", "Base")


def _numbers(value, turns=True):
    """The numbers in `value` (float, Quantity, Vector, Placement, list): a Placement's
    position, and its rotation's quaternion when `turns`."""
    if isinstance(value, (list, tuple)):
        for v in value:
            yield from _numbers(v, turns)
    elif hasattr(value, "Value") and not isinstance(value, str):  # Quantity
        yield value.Value
    elif hasattr(value, "Rotation"):  # Placement
        yield from _numbers(value.Base)
        if turns:
            yield from value.Rotation.Q
    elif hasattr(value, "x") and hasattr(value, "z"):  # Vector
        yield from (value.x, value.y, value.z)
    else:
        yield value


def _finite(value):
    """False if a number in `value` (see _numbers) is NaN or infinite."""
    # a length property clamps infinity to the largest float: that is infinity too
    return all(not isinstance(x, float) or (math.isfinite(x) and abs(x) < sys.float_info.max)
               for x in _numbers(value))


LARGEST = 1e9  # mm: beyond it doubles lie farther apart than OCCT's 1e-7 mm Confusion
LENGTHS = ("App::PropertyLength", "App::PropertyDistance", "App::PropertyVectorDistance",
           "App::PropertyVectorList", "App::PropertyPlacement", "App::PropertyPlacementList")


def _largest(value):
    """The largest coordinate or length (mm) in `value`: a length Quantity, a Vector, a
    Placement's position, or a list of them."""
    return max((abs(x) for x in _numbers(value, turns=False)), default=0.0)


def check_magnitudes(obj, properties):
    """No length or position beyond LARGEST: there OCCT can no longer tell points apart
    (its errors would name nothing the user set)."""
    for p in properties:
        if p.output or not (p.type in LENGTHS or p.unit == "mm"):
            continue
        largest = _largest(getattr(obj, p.name))
        if largest > LARGEST:
            raise DeformError(f"{p.name} reaches {largest:.3g} mm, beyond 1e9 mm, where OCCT "
                              f"can no longer tell points 1e-7 mm apart; give {p.name} a "
                              f"value under 1e9 mm.", p.name)


def check_finite(obj, properties):
    """Every number the user set must be finite: NaN or infinity would reach OCCT and the
    solvers (some never return)."""
    for p in properties:
        if p.output or p.type.startswith(("App::PropertyLink", "App::PropertyString",
                                          "App::PropertyEnumeration", "App::PropertyBool")):
            continue
        if not _finite(getattr(obj, p.name)):
            raise DeformError(f"{p.name} holds a value that is not a finite number (NaN or "
                              f"infinity); give {p.name} a finite value.", p.name)


def _keep_unit(obj, p):
    """Give quantity property `p` its unit: FreeCAD saves a PropertyQuantity's value but
    not its unit, and an older document may hold it as a bounded type (PropertyAngle
    stops at 360 deg), which is replaced keeping its value and expression."""
    import FreeCAD as App
    if obj.getTypeIdOfProperty(p.name) != p.type:
        value = getattr(obj, p.name).Value
        expression = dict(obj.ExpressionEngine).get(p.name)
        obj.removeProperty(p.name)
        obj.addProperty(p.type, p.name, p.group, p.doc, OUTPUT if p.output else 0)
        setattr(obj, p.name, App.Units.Unit(p.unit))
        setattr(obj, p.name, value)
        if expression:
            obj.setExpression(p.name, expression)
    elif getattr(obj, p.name).Unit != App.Units.Unit(p.unit):
        setattr(obj, p.name, App.Units.Unit(p.unit))


class Stateless:
    """A proxy that saves nothing of its own (its object's properties hold everything):
    FreeCAD stores None, never a pickle."""

    def dumps(self):
        return None

    def loads(self, state):
        return None

    __getstate__ = dumps  # FreeCAD 0.20 calls these names
    __setstate__ = loads


class DeformFeature(Stateless):
    """Proxy base: properties added when missing (also on restore), JSON-only state.

    Subclasses list PROPERTIES and implement compute(obj, base_kind) -> (result, outputs):
    the new Shape, Mesh or Points and a dict of output property values. Bad input raises
    DeformError naming the property to change; FreeCAD then marks the object in error
    and keeps its last good result. The Base is only read.
    """

    TYPE = "Deform"
    PROPERTIES = ()

    def __init_subclass__(cls, **kwargs):
        """A subclass that writes its own execute() gets the checks every feature needs
        (check_inputs) run first all the same."""
        super().__init_subclass__(**kwargs)
        own = cls.__dict__.get("execute")
        if own is not None:
            @functools.wraps(own)
            def execute(self, obj):
                with self.recording():
                    self.check_inputs(obj)
                    return own(self, obj)
            cls.execute = execute

    @contextlib.contextmanager
    def recording(self):
        """Keep the property a refusal names in `error_prop` (None after a success), so a
        task panel can mark that field; FreeCAD itself keeps only the message."""
        self.error_prop = None
        try:
            yield
        except DeformError as e:
            self.error_prop = e.prop
            raise

    def check_inputs(self, obj):
        """No self-link or cycle through Base, no NaN or infinite property value, no
        length beyond LARGEST."""
        check_links(obj)
        check_finite(obj, self.PROPERTIES)
        check_magnitudes(obj, self.PROPERTIES)

    def __init__(self, obj):
        obj.Proxy = self
        self.ensure_properties(obj)

    def ensure_properties(self, obj):
        existing = set(obj.PropertiesList)
        for p in self.PROPERTIES:
            if p.name in existing:
                if p.unit:
                    _keep_unit(obj, p)
                continue
            obj.addProperty(p.type, p.name, p.group, p.doc, OUTPUT if p.output else 0)
            if p.unit:
                _keep_unit(obj, p)
            if p.default is not None:
                setattr(obj, p.name, p.default)

    def onDocumentRestored(self, obj):
        self.ensure_properties(obj)

    def execute(self, obj):
        with self.recording():
            self._execute(obj)

    def _execute(self, obj):
        self.check_inputs(obj)
        kind = base_kind(obj.Base)
        if not hasattr(self, "RESULT") and obj.TypeId != RESULT_TYPES[kind]:
            was = next(k for k, t in RESULT_TYPES.items() if t == obj.TypeId)
            raise DeformError(f"Base {obj.Base.Label} is a {KIND_WORDS[kind]}, but {obj.Label} "
                              f"was made for a {KIND_WORDS[was]} and holds one; link a "
                              f"{KIND_WORDS[was]}, or make a new {self.TYPE} on "
                              f"{obj.Base.Label}.", "Base")
        result, outputs = self.compute(obj, kind)
        if kind == "Part":
            result = placed_in_geometry(result)
        setattr(obj, {"Part": "Shape", "Mesh": "Mesh", "Points": "Points"}[kind], result)
        for name, value in outputs.items():
            setattr(obj, name, value)

    def compute(self, obj, base_kind):
        raise NotImplementedError


def placed_in_geometry(shape):
    """`shape` with its Placement moved into its geometry. A result that keeps the Base's
    own Placement (a face pushed or constrained in place, the rest of the Base kept)
    would lose it: FreeCAD gives a feature's Shape the object's Placement (identity)
    after execute, and the part jumped to its local frame (OCCT's Pump_TopCover.brep)."""
    placement = shape.Placement
    if placement.isIdentity():
        return shape
    baked = shape.copy()
    baked.Placement = type(placement)()
    baked.transformShape(placement.toMatrix(), True)
    return baked
