"""Running a script inside the FreeCAD GUI on a virtual screen (xvfb-run), with this
workbench installed the way a user installs it: linked into the user Mod folder of a
throwaway HOME (Debian's FreeCAD restores document objects only from installed add-ons).
Used by the demo's pictures and the GUI tests."""
import os
import shutil
import subprocess

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
SCREEN = "-screen 0 1280x1024x24"


def tool(*names):
    """The path of the first of `names` on PATH; FileNotFoundError naming what to install."""
    for name in names:
        path = shutil.which(name)
        if path:
            return path
    raise FileNotFoundError(f"{' or '.join(names)} not found: install it (Debian: apt-get "
                            f"install freecad xvfb xauth)")


def environment(home, **extra):
    """The environment of a FreeCAD run in `home`: no user settings, display or PYTHONPATH
    leak in; Qt WebEngine allowed to run as root."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("XDG_", "FREECAD_"))
           and k not in ("DISPLAY", "PYTHONPATH")}
    env.update(HOME=str(home), QTWEBENGINE_CHROMIUM_FLAGS="--no-sandbox", LANG="C.UTF-8",
               LC_ALL="C.UTF-8", DEFORM_REPO=REPO, **extra)
    return env


def install(home):
    """Link this repository as the Deform add-on into the user Mod folder FreeCAD uses for
    `home` (asked from FreeCAD itself); returns that folder."""
    probe, answer = os.path.join(home, "probe_user_dir.py"), os.path.join(home, "user_dir.txt")
    with open(probe, "w") as f:
        f.write(f"import FreeCAD\nopen({answer!r}, 'w').write(FreeCAD.getUserAppDataDir())\n")
    subprocess.run([tool("freecadcmd", "FreeCADCmd"), probe], env=environment(home),
                   capture_output=True, timeout=60)
    if not os.path.exists(answer):
        raise RuntimeError("freecadcmd did not report its user data directory")
    with open(answer) as f:
        mod = os.path.join(f.read().strip(), "Mod")
    os.makedirs(mod, exist_ok=True)
    link = os.path.join(mod, "Deform")
    if not os.path.islink(link):
        os.symlink(REPO, link)
    return mod


def run_script(script, home, timeout, **extra):
    """Run `script` in the FreeCAD GUI under xvfb-run in `home` (install() first); the
    script ends FreeCAD itself. Returns the CompletedProcess (text output)."""
    command = [tool("xvfb-run"), "-a", "-s", SCREEN, tool("freecad", "FreeCAD"), script]
    return subprocess.run(command, env=environment(home, **extra), cwd=str(home),
                          capture_output=True, encoding="utf-8", errors="replace",
                          timeout=timeout)
