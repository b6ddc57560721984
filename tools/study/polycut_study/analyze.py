"""From job results to rows: cost and error of every run, and the Pareto front per problem."""
import json
import math
import os

from . import references
from .execute import result_path

# Columns of rows.csv, in order (docs/study.md, "Outputs").
COLUMNS = [
    "index", "problem", "label", "group", "ok", "message",
    "nodes", "cells", "dofs", "free_dofs", "nonzeros",
    "setup_ms", "setup_cpu_ms", "step_ms", "step_ms_p99", "step_cpu_ms", "step_cpu_ms_p99",
    "peak_rss_mb", "steps", "iterations", "rolled_back",
    "error", "error_kind", "measured", "exact", "probe_error", "field_points", "pareto",
]


def _group(assignment, group_by):
    """The marker of a run in plots: its method-like axes ("hex mean_dilatation")."""
    parts = [str(assignment[k]) for k in group_by if k in assignment]
    return " ".join(parts) if parts else "base"


def _load(out, index):
    try:
        with open(result_path(out, index)) as f:
            return json.load(f)
    except (OSError, json.JSONDecodeError):
        return None


def collect(study, out):
    """Rows (dicts with COLUMNS) of every job that has a result; missing ones are listed as
    not ok with message "no result"."""
    results = [_load(out, i) for i in range(len(study.jobs))]
    digest = study.digest()
    reference = {}
    for r in results:
        if r and r.get("digest") == digest and r["kind"] == "reference" and r["ok"]:
            reference[r["problem"]] = r["report"]
    rows = []
    for i, j in enumerate(study.jobs):
        r = results[i]
        row = {c: None for c in COLUMNS}
        row.update(index=i, problem=j["problem"], label=j["label"],
                   group="reference" if j["kind"] == "reference"
                   else _group(j["assignment"], study.problem(j["problem"])["group_by"]),
                   ok=False, message="no result", pareto=False)
        if r is None or r.get("digest") != digest:
            rows.append(row)
            continue
        row["ok"], row["message"] = r["ok"], r["message"]
        rep = r["report"]
        if rep:
            t, c, m = rep["timing"], rep["cost"], rep["model"]
            row.update(nodes=rep["mesh"]["nodes"], cells=rep["mesh"]["cells"], dofs=m["dofs"],
                       free_dofs=m["free_dofs"], nonzeros=m["nonzeros"],
                       setup_ms=c["setup_ms"], setup_cpu_ms=c["setup_cpu_ms"],
                       step_ms=t["step_ms"]["median"], step_ms_p99=t["step_ms"]["p99"],
                       step_cpu_ms=c["step_cpu_ms"]["median"], step_cpu_ms_p99=c["step_cpu_ms"]["p99"],
                       peak_rss_mb=c["peak_rss_mb"], steps=rep["steps"],
                       iterations=rep["solver"]["iterations"]["median"],
                       rolled_back=rep["solver"]["rolled_back_steps"])
            _error(study, j, rep, reference.get(j["problem"]), row)
        rows.append(row)
    for problem in study.problems:
        mark_pareto([r for r in rows if r["problem"] == problem["name"]], study.cost)
    return rows


def _error(study, j, rep, ref_report, row):
    ref = study.problem(j["problem"])["reference"]
    if "analytic" in ref:
        e, m, x = references.analytic_error(ref, j["scene"], rep)
        row.update(error=e, error_kind=f"analytic {ref['analytic']}", measured=m, exact=x)
        return
    if j["kind"] == "reference":
        row.update(error_kind="reference")
        return
    if ref_report is None:
        row.update(error=math.nan, error_kind="converged (reference missing)")
        return
    e, n = references.field_error(rep, ref_report)
    row.update(error=e, error_kind="converged field", field_points=n,
               probe_error=references.probe_error(rep, ref_report))
    if rep["solver"]["rolled_back_steps"] > 0 and not math.isnan(e):
        row["message"] = (row["message"] + "; " if row["message"] else "") + \
            f"{rep['solver']['rolled_back_steps']} rolled-back steps"


def _finite(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def mark_pareto(rows, cost="step_ms"):
    """Sets row["pareto"] on the runs no other run beats in both cost and error (ties in both
    keep the first); runs without a finite cost and error are never on the front."""
    cand = [r for r in rows if r["ok"] and r["group"] != "reference"
            and _finite(r.get(cost)) and _finite(r.get("error"))]
    for r in rows:
        r["pareto"] = False
    for r in cand:
        dominated = any(
            (o[cost] <= r[cost] and o["error"] <= r["error"])
            and (o[cost] < r[cost] or o["error"] < r["error"] or o["index"] < r["index"])
            for o in cand if o is not r)
        r["pareto"] = not dominated
    return [r for r in cand if r["pareto"]]


def front(rows, problem, cost="step_ms"):
    """The Pareto front of a problem, cheapest first."""
    return sorted((r for r in rows if r["problem"] == problem and r["pareto"]), key=lambda r: r[cost])


def ensure_dir(path):
    os.makedirs(path, exist_ok=True)
    return path
