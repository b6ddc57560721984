"""Outputs of a study (docs/study.md, "Outputs"): rows.csv, rows.json, pareto.json, table.md and
one plot per problem (error against cost per step, log-log, one marker per method, the front)."""
import csv
import json
import math
import os
import sys

from .analyze import COLUMNS, ensure_dir, front

_COST_TITLE = {
    "step_ms": "wall time per step, median [ms]",
    "step_ms_p99": "wall time per step, p99 [ms]",
    "step_cpu_ms": "CPU time per step, median [ms]",
    "setup_ms": "set-up time [ms]",
}


def _clean(v):
    return None if isinstance(v, float) and not math.isfinite(v) else v


def write_rows(study, rows, out):
    with open(os.path.join(out, "rows.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r[k] is None else r[k]) for k in COLUMNS})
    with open(os.path.join(out, "rows.json"), "w") as f:
        json.dump({"study": study.name, "digest": study.digest(), "cost": study.cost,
                   "rows": [{k: _clean(r[k]) for k in COLUMNS} for r in rows]}, f, indent=1)
    fronts = {p["name"]: [{k: _clean(r[k]) for k in ("index", "label", "group", study.cost, "error")}
                          for r in front(rows, p["name"], study.cost)] for p in study.problems}
    with open(os.path.join(out, "pareto.json"), "w") as f:
        json.dump({"study": study.name, "cost": study.cost, "fronts": fronts}, f, indent=1)


def _fmt(v, spec):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return format(v, spec)


def write_table(study, rows, out, command):
    lines = [f"# Study {study.name}", "", study.doc.get("description", ""), "",
             f"Made by `{command}`. Cost: {_COST_TITLE[study.cost]}; error: relative, against the "
             "problem's reference; * = on the Pareto front (no run is both cheaper and more "
             "accurate).", ""]
    for p in study.problems:
        ref = p["reference"]
        what = (f"analytic ({ref['analytic']}, probe {ref['probe']})" if "analytic" in ref
                else f"converged run ({json.dumps(ref['converged'])}), displacement field at "
                     f"{len(p['samples'])} lattice points")
        lines += [f"## {p['name']}", ""] + ([p["description"], ""] if p["description"] else []) + [
                  f"Reference: {what}.", "",
                  "| | run | nodes | DOFs | nonzeros | set-up [ms] | step median [ms] | step p99 [ms] "
                  "| CPU/step [ms] | memory [MB] | error |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        mine = [r for r in rows if r["problem"] == p["name"]]
        mine.sort(key=lambda r: (r[study.cost] is None, r[study.cost] or 0))
        for r in mine:
            if not r["ok"]:
                lines.append(f"| | {r['label']} | failed: {r['message']} | | | | | | | | |")
                continue
            lines.append(
                f"| {'*' if r['pareto'] else ''} | {r['label']} | {r['nodes']} | {r['free_dofs']} | "
                f"{r['nonzeros']} | {_fmt(r['setup_ms'], '.0f')} | {_fmt(r['step_ms'], '.3g')} | "
                f"{_fmt(r['step_ms_p99'], '.3g')} | {_fmt(r['step_cpu_ms'], '.3g')} | "
                f"{_fmt(r['peak_rss_mb'], '.0f')} | "
                f"{'reference' if r['group'] == 'reference' else _fmt(r['error'], '.2e')} |")
        lines.append("")
    with open(os.path.join(out, "table.md"), "w") as f:
        f.write("\n".join(lines))


def _pyplot():
    """pyplot in polycut's figure style, the one polycut-bench's histograms use
    (clients/python/polycut/plots.py)."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                                    "clients", "python"))
    from polycut.plots import apply_style
    return apply_style()


def plot(study, rows, out, command):
    """One PNG per problem; returns their paths."""
    plt = _pyplot()
    markers = "osD^v<>phX*P"
    plots = ensure_dir(os.path.join(out, "plots"))
    paths = []
    for p in study.problems:
        groups = sorted({r["group"] for r in rows if r["problem"] == p["name"] and r["group"] != "reference"})
        style = {g: markers[i % len(markers)] for i, g in enumerate(groups)}
        mine = [r for r in rows if r["problem"] == p["name"] and r["ok"] and r["group"] != "reference"
                and r[study.cost] and r["error"] is not None and math.isfinite(r["error"])]
        fig, axes = plt.subplots(figsize=(6.4, 4.6))
        floor = 1e-12
        for g in groups:
            pts = [r for r in mine if r["group"] == g]
            if pts:
                axes.loglog([r[study.cost] for r in pts], [max(r["error"], floor) for r in pts],
                            style[g], label=g, alpha=0.8, markersize=7, markerfacecolor="none")
        f = [r for r in front(rows, p["name"], study.cost) if r in mine]
        if f:
            axes.loglog([r[study.cost] for r in f], [max(r["error"], floor) for r in f], "k-",
                        linewidth=1, label="Pareto front", zorder=0, drawstyle="steps-post")
        axes.set_xlabel(_COST_TITLE[study.cost])
        axes.set_ylabel("relative error")
        axes.set_title(f"{study.name}: {p['name']}")
        axes.grid(True, which="both", alpha=0.3)
        if mine:
            axes.legend(fontsize=8)
        fig.text(0.01, 0.005, command, fontsize=6, color="gray")
        fig.tight_layout()
        path = os.path.join(plots, f"{p['name']}.png")
        fig.savefig(path, dpi=110)
        plt.close(fig)
        paths.append(path)
    return paths
