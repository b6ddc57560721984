"""polycut-study: the speed/accuracy trade of polycut's methods, measured (docs/study.md).

  polycut-study run STUDY.json --out DIR [--jobs N] [--force]   all jobs here, then collect
  polycut-study list STUDY.json                                  the job list: index -> run
  polycut-study run-one STUDY.json --out DIR [--index I]         one job (cluster task)
  polycut-study collect STUDY.json --out DIR                     rows, fronts, table, plots
  polycut-study plan STUDY.json --out DIR --slurm|--k8s|--parallel
Exit status: 0 done, 1 some run failed (its row says why), 2 bad study or arguments.
"""
import argparse
import os
import shlex
import sys

from . import analyze, execute, plan, report
from .study import Study, StudyError, index_from_environment


def _tool_path():
    return os.environ.get("POLYCUT_STUDY") or os.path.abspath(sys.argv[0])


def _collect(study, out, command):
    rows = analyze.collect(study, out)
    report.write_rows(study, rows, out)
    report.write_table(study, rows, out, command)
    plots = report.plot(study, rows, out, command)
    failed = [r for r in rows if not r["ok"]]
    for p in study.problems:
        f = analyze.front(rows, p["name"], study.cost)
        best = ", ".join(f"{r['label'] or 'base'} ({r[study.cost]:.3g} ms, {r['error']:.2e})" for r in f)
        print(f"{p['name']}: front {best or '(empty)'}")
    print(f"wrote {out}/rows.csv, rows.json, pareto.json, table.md and {len(plots)} plots"
          + (f"; {len(failed)} runs failed" if failed else ""))
    return 1 if failed else 0


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(prog="polycut-study", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    for name in ("run", "list", "run-one", "collect", "plan"):
        p = sub.add_parser(name)
        p.add_argument("study")
        if name != "list":
            p.add_argument("--out", required=True, help="output directory")
        if name in ("run", "run-one"):
            p.add_argument("--runner", help="polycut-run to use (default: $POLYCUT_RUN, PATH)")
        if name == "run":
            p.add_argument("--jobs", type=int, help="processes (default: all cores)")
            p.add_argument("--force", action="store_true", help="rerun jobs that have a result")
        if name == "run-one":
            p.add_argument("--index", type=int,
                           help="job index (default: $SLURM_ARRAY_TASK_ID or $JOB_COMPLETION_INDEX)")
        if name == "plan":
            g = p.add_mutually_exclusive_group(required=True)
            g.add_argument("--slurm", action="store_true")
            g.add_argument("--k8s", action="store_true")
            g.add_argument("--parallel", action="store_true", help="GNU parallel commands")
            p.add_argument("--image", default="polycut:latest", help="k8s: container image")
            p.add_argument("--claim", default="polycut-study", help="k8s: volume claim")
            p.add_argument("--time", default="01:00:00", help="slurm: time limit per task")
            p.add_argument("--tool", help="polycut-study path on the cluster (default: this one)")
    a = ap.parse_args(argv)
    try:
        study = Study(a.study)
    except StudyError as e:
        print(f"polycut-study: {e}", file=sys.stderr)
        return 2
    command = "polycut-study " + " ".join(shlex.quote(x) for x in argv)
    if a.cmd == "list":
        for j in study.jobs:
            note = f"  [cannot run: {j['error']}]" if j["error"] else ""
            print(f"{j['index']:4d}  {j['problem']:<16} {j['label']}{note}")
        return 0
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    if a.cmd == "run":
        execute.run_all(study, out, a.runner, a.jobs, a.force)
        return _collect(study, out, command)
    if a.cmd == "run-one":
        index = a.index if a.index is not None else index_from_environment()
        if index is None:
            print("polycut-study: run-one needs --index or SLURM_ARRAY_TASK_ID / JOB_COMPLETION_INDEX",
                  file=sys.stderr)
            return 2
        try:
            r = execute.run_job(study, index, out, a.runner)
        except StudyError as e:
            print(f"polycut-study: {e}", file=sys.stderr)
            return 2
        print(f"[{index}] {'ok' if r['ok'] else 'FAIL'} {r['problem']}: {r['label']} {r['message']}")
        return 0 if r["ok"] else 1
    if a.cmd == "collect":
        return _collect(study, out, command)
    tool = a.tool or _tool_path()
    d = analyze.ensure_dir(os.path.join(out, "plan"))
    if a.slurm:
        files = {"study.sbatch": plan.slurm(study, out, tool, a.time),
                 "collect.sbatch": plan.slurm_collect(study, out, tool)}
        os.makedirs(os.path.join(out, "logs"), exist_ok=True)  # Slurm does not create it
    elif a.k8s:
        try:
            files = {"study-job.yaml": plan.kubernetes(study, out, tool, a.image, a.claim)}
        except ValueError as e:
            print(f"polycut-study: {e}", file=sys.stderr)
            return 2
    else:
        files = {"parallel.sh": plan.gnu_parallel(study, out, tool)}
    for name, text in files.items():
        with open(os.path.join(d, name), "w") as f:
            f.write(text)
        print(os.path.join(d, name))
    return 0
