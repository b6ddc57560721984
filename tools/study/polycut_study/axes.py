"""What each study axis changes in a scene (docs/study.md, "Axes").

apply(scene, assignment) returns a new scene dict with every axis value written into it; the
scene loader (polycut-run) validates the result, so a combination the simulator refuses shows up
as a failed row with the loader's message, not as a crash of the study.
"""
import copy
import math

AXES = ("method", "element", "resolution", "quadrature", "corotation", "solver",
        "preconditioner", "tolerance", "dt", "threads")

class AxisError(ValueError):
    """A value an axis cannot apply to this scene (the message says which and why)."""


def _set_pointer(doc, pointer, value):
    """Sets doc at a JSON pointer ("/solver/tolerance"), creating objects on the way."""
    parts = [p.replace("~1", "/").replace("~0", "~") for p in pointer.split("/")[1:]]
    if not parts:
        raise AxisError(f"{pointer}: cannot replace the whole scene")
    node = doc
    for p in parts[:-1]:
        if isinstance(node, list):
            node = node[int(p)]
        else:
            node = node.setdefault(p, {})
    if isinstance(node, list):
        node[int(parts[-1])] = value
    else:
        node[parts[-1]] = value


def merge_patch(target, patch):
    """RFC 7386 JSON merge patch (null deletes a key), in place; returns target."""
    for k, v in patch.items():
        if v is None:
            target.pop(k, None)
        elif isinstance(v, dict) and isinstance(target.get(k), dict):
            merge_patch(target[k], v)
        else:
            target[k] = copy.deepcopy(v)
    return target


def _method(scene, value):
    name, _, rule = str(value).partition(":")
    geo = scene["geometry"]
    if name in ("tet", "hex"):
        if geo["type"] == "random_planes":
            geo["type"] = "box"
            geo.pop("planes_per_cell", None)
        if geo["type"] == "box":
            geo["elements"] = name
        elif name == "hex":
            raise AxisError(f"method hex needs a box geometry, not {geo['type']}")
    elif name in ("mvc", "harmonic"):
        # Polyhedral bases act on cells that are neither tets nor hexes: random-plane polyhedra
        # (seed 000 Fig. 2) keep their cells; a box grid becomes hexes, Q1 until a cut splits
        # them into polyhedra (as in assets/scenes/cut_halves.json). A base scene of random
        # planes compares all methods on one problem (tet and hex turn it back into a box).
        if geo["type"] == "box":
            geo["elements"] = "hex"
            geo.pop("tet_split", None)
    elif name != "dg":
        raise AxisError(f"unknown method {value!r}")
    scene["method"] = name
    if rule:
        scene.setdefault("basis", {})["rule"] = rule


def _resolution(scene, factor):
    """Refinement factor relative to the base scene: box cells x factor, Mesh_3 cell_size / factor."""
    if not (isinstance(factor, (int, float)) and factor > 0):
        raise AxisError(f"resolution must be a positive number, got {factor!r}")
    geo = scene["geometry"]
    if geo["type"] in ("box", "random_planes"):
        cells = geo.get("cells", [4, 4, 4])
        geo["cells"] = [max(1, int(round(c * factor))) for c in cells]
    elif geo["type"] in ("implicit", "surface_file"):
        geo["cell_size"] = geo["cell_size"] / factor
    else:
        raise AxisError(f"resolution cannot refine a {geo['type']} geometry")


def _dt(scene, dt, duration):
    scene.setdefault("integrator", {})["dt"] = dt
    if duration is not None:
        scene.setdefault("output", {})["steps"] = max(1, int(round(duration / dt)))


def base_duration(scene, steps=None):
    """Simulated time of the base scene [s]: dt x steps (None for a static scene)."""
    it = scene.get("integrator", {})
    if it.get("type", "implicit_euler") == "static":
        return None
    n = steps if steps is not None else scene.get("output", {}).get("steps", 100)
    return it.get("dt", 0.01) * n


def apply(scene, assignment, duration=None):
    """A copy of `scene` with each axis of `assignment` ({axis: value}) applied, in the order
    of AXES (method before resolution, so random planes get the refined cells), then the JSON
    pointer axes. `duration` [s] keeps the simulated time when dt varies."""
    out = copy.deepcopy(scene)
    for axis in AXES:
        if axis not in assignment:
            continue
        v = assignment[axis]
        if axis == "method":
            _method(out, v)
        elif axis == "element":
            if v not in ("full", "mean_dilatation", "nodal_average"):
                raise AxisError(f"element must be full, mean_dilatation or nodal_average, got {v!r}")
            out.setdefault("basis", {})["volumetric"] = v
        elif axis == "resolution":
            _resolution(out, v)
        elif axis == "quadrature":
            out.setdefault("basis", {})["gauss_degree"] = int(v)
        elif axis == "corotation":
            out.setdefault("integrator", {})["corotated"] = bool(v)
        elif axis == "solver":
            out.setdefault("solver", {})["type"] = v
        elif axis == "preconditioner":
            s = out.setdefault("solver", {})
            if "solver" not in assignment:
                s["type"] = "pcg"
            s["preconditioner"] = v
        elif axis == "tolerance":
            out.setdefault("solver", {})["tolerance"] = float(v)
        elif axis == "dt":
            _dt(out, float(v), duration)
        elif axis == "threads":
            out.setdefault("integrator", {})["threads"] = int(v)
    for axis, v in assignment.items():
        if axis.startswith("/"):
            _set_pointer(out, axis, copy.deepcopy(v))
    return out


def label(assignment):
    """Short text of an assignment: "method=tet resolution=0.5"."""
    def fmt(v):
        if isinstance(v, float):
            return f"{v:g}"
        return str(v).lower() if isinstance(v, bool) else str(v)
    return " ".join(f"{k}={fmt(v)}" for k, v in assignment.items())


def is_finite_number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)
