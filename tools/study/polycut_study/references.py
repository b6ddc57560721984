"""References a run's error is measured against (docs/study.md, "References").

Analytic: a closed-form displacement at a probe, computed from the run's own scene (material,
geometry, loads), so a study that varies them stays right:
  cantilever_002  seed 002 sec. 3.3: tip deflection 8.64e-3 m, compared with |u(probe)|
  bar_gravity     a bar hanging under its own weight, nu = 0: w = rho g L^2 / (2 E) at the free
                  end, compared with u(probe) . g / |g|; L = the box's extent along g
  lame_sphere     Lame's thick-walled sphere under internal pressure p (the first pressure
                  load): u_r(a) = p a^3 / (E (b^3 - a^3)) ((1 - 2 nu) a + (1 + nu) b^3 / (2 a^2)),
                  compared with the radial part of u(probe); a, b from the hollow_sphere geometry.
                  With `opposite` (a second probe), every kind compares half the change of the
                  distance between the two probes instead: no rigid motion changes it, so a
                  free body held by 3-2-1 supports is measured exactly
  value           a given number (`value`) against a component of u(probe) (`component`)
Converged: a run of the same problem at the reference's settings (finer, tighter); runs are
compared with it as displacement fields at lattice points inside the tissue (relative l2 over
the points inside both), and at the probes.
"""
import math

import numpy as np


def _probe_point(scene, name, where):
    for p in scene.get("probes", []):
        if p["name"] == name:
            return np.array(p["point"], float)
    raise ValueError(f"{where}/probe: the scene has no probe {name!r}")


def check_analytic(ref, scene, where):
    """Raises ValueError (naming the field) when the scene cannot have this analytic value."""
    from .study import StudyError
    try:
        if "probe" not in ref:
            raise ValueError(f"{where}/probe: an analytic reference needs a probe")
        _probe_point(scene, ref["probe"], where)
        if "opposite" in ref:
            _probe_point(scene, ref["opposite"], where)
        kind = ref["analytic"]
        if kind == "value" and "value" not in ref:
            raise ValueError(f"{where}/value: \"value\" needs the number")
        analytic_value(ref, scene)
    except (ValueError, KeyError) as e:
        raise StudyError(str(e)) from None


def analytic_value(ref, scene):
    """The exact value [m] the measured quantity is compared with."""
    kind = ref["analytic"]
    mat = scene["material"]
    E, nu, rho = mat["youngs_modulus"], mat.get("poisson_ratio", 0.45), mat.get("density", 1000)
    if kind == "cantilever_002":
        return 8.64e-3
    if kind == "value":
        return float(ref["value"])
    if kind == "bar_gravity":
        g = np.array(scene.get("loads", {}).get("gravity", [0, 0, 0]), float)
        geo = scene["geometry"]
        if not np.linalg.norm(g) > 0 or geo["type"] not in ("box", "random_planes") or "size" not in geo:
            raise ValueError("bar_gravity needs gravity and a box geometry with a size")
        L = float(np.dot(np.abs(g) / np.linalg.norm(g), geo["size"]))
        return rho * np.linalg.norm(g) * L * L / (2 * E)
    if kind == "lame_sphere":
        geo = scene["geometry"]
        pressures = scene.get("loads", {}).get("pressure", [])
        if geo.get("shape") != "hollow_sphere" or not pressures:
            raise ValueError("lame_sphere needs a hollow_sphere geometry and a pressure load")
        a, b, p = geo["inner_radius"], geo["radius"], pressures[0]["pressure"]
        return p * a ** 3 / (E * (b ** 3 - a ** 3)) * ((1 - 2 * nu) * a + (1 + nu) * b ** 3 / (2 * a * a))
    raise ValueError(f"unknown analytic reference {kind!r}")


def measured(ref, scene, report):
    """The quantity of a run's report that analytic_value() is the exact value of [m]."""
    u = np.array(report["probes"][ref["probe"]]["displacement"], float)
    kind = ref["analytic"]
    if "opposite" in ref:
        v = np.array(report["probes"][ref["opposite"]]["displacement"], float)
        d = _probe_point(scene, ref["probe"], "") - _probe_point(scene, ref["opposite"], "")
        return float(np.dot(u - v, d / np.linalg.norm(d)) / 2)
    if kind == "cantilever_002":
        return float(np.linalg.norm(u))
    if kind == "bar_gravity":
        g = np.array(scene["loads"]["gravity"], float)
        return float(np.dot(u, g / np.linalg.norm(g)))
    if kind == "lame_sphere":
        X = _probe_point(scene, ref["probe"], "")
        c = np.array(scene["geometry"].get("center", [0, 0, 0]), float)
        return float(np.dot(u, (X - c) / np.linalg.norm(X - c)))
    comp = ref.get("component", "magnitude")
    return float(np.linalg.norm(u)) if comp == "magnitude" else float(u["xyz".index(comp)])


def analytic_error(ref, scene, report):
    """(relative error, measured, exact) of a run against its analytic reference."""
    exact = analytic_value(ref, scene)
    m = measured(ref, scene, report)
    return abs(m - exact) / abs(exact), m, exact


def _bounds(geo):
    t = geo["type"]
    if t in ("box", "random_planes"):
        if "corners" in geo:
            c = np.array(geo["corners"], float)
            return c.min(axis=0), c.max(axis=0)
        lo = np.array(geo.get("origin", [0, 0, 0]), float)
        return lo, lo + np.array(geo["size"], float)
    if t == "implicit":
        c = np.array(geo.get("center", [0, 0, 0]), float)
        shape = geo["shape"]
        if shape in ("sphere", "hollow_sphere"):
            r = np.full(3, geo["radius"])
        elif shape == "capsule":
            r = np.array([geo["radius"], geo["radius"], geo["radius"] + 0.5 * geo["length"]])
        elif shape == "ellipsoid":
            r = np.array(geo["radii"], float)
        else:  # blob: its reference shape spans about [-1, 1] x [-0.7, 0.6] x [-0.5, 0.45]
            r = np.array(geo.get("radii", [0.05] * 3), float) * np.array([1.05, 0.75, 0.55])
        return c - r, c + r
    return None


def sample_points(ref, scene, where):
    """Lattice points (cell centres of an nx x ny x nz lattice over a box) where runs are
    compared with a converged reference; points outside the tissue are dropped per run."""
    from .study import StudyError
    spec = ref.get("samples", {})
    n = spec.get("lattice", [6, 6, 6])
    if "box" in spec:
        lo, hi = np.array(spec["box"]["min"], float), np.array(spec["box"]["max"], float)
    else:
        b = _bounds(scene["geometry"])
        if b is None:
            raise StudyError(f"{where}/samples/box: give the box for a {scene['geometry']['type']} geometry")
        lo, hi = b
    pts = []
    for k in range(n[2]):
        for j in range(n[1]):
            for i in range(n[0]):
                f = (np.array([i, j, k]) + 0.5) / np.array(n)
                pts.append([float(x) for x in lo + f * (hi - lo)])
    return pts


def field_error(report, reference_report):
    """Relative l2 error of the sampled displacement field against the reference's, over the
    points inside the tissue in both: sqrt(sum |u - u_ref|^2 / sum |u_ref|^2); and the count."""
    a, b = report.get("samples"), reference_report.get("samples")
    if not a or not b or a["count"] != b["count"]:
        return math.nan, 0
    u = np.array(a["displacement"], float)
    r = np.array(b["displacement"], float)
    both = np.array(a["inside"], bool) & np.array(b["inside"], bool)
    if not both.any():
        return math.nan, 0
    den = np.sum(r[both] ** 2)
    if not den > 0:
        return math.nan, int(both.sum())
    return float(math.sqrt(np.sum((u[both] - r[both]) ** 2) / den)), int(both.sum())


def probe_error(report, reference_report):
    """Largest relative probe displacement error against the reference (nan without probes)."""
    worst = math.nan
    for name, p in report.get("probes", {}).items():
        q = reference_report.get("probes", {}).get(name)
        if not q or not q["magnitude"] > 0:
            continue
        e = np.linalg.norm(np.array(p["displacement"]) - np.array(q["displacement"])) / q["magnitude"]
        worst = e if math.isnan(worst) else max(worst, e)
    return float(worst)
