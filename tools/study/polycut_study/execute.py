"""Running jobs: one job through the headless runner (run_job, what a cluster task calls), and
all of them on the local cores with a process pool (run_all). No scheduler of our own: a task is
one index of the job list, and the result is a file named by that index."""
import concurrent.futures
import json
import os
import shutil
import subprocess
import sys
import time

from .study import job as job_at


def default_runner():
    """polycut-run: $POLYCUT_RUN, else the build tree's (set by the launcher), else on PATH."""
    return os.environ.get("POLYCUT_RUN") or shutil.which("polycut-run") or "polycut-run"


def result_path(out, index):
    return os.path.join(out, "jobs", f"{index:05d}.json")


def _write_json(path, doc):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    # A temporary name per process: two pool workers may write the same file (the samples of
    # a problem, written by whichever of its jobs comes first), and with one shared name the
    # second os.replace found the first's temporary gone (a FileNotFoundError that failed the
    # whole run, now and then, in study_tiny).
    tmp = f"{path}.{os.getpid()}.tmp"
    with open(tmp, "w") as f:
        json.dump(doc, f, indent=1)
    os.replace(tmp, path)  # readers never see half a file


def run_job(study, index, out, runner=None):
    """Runs job `index` of `study` and writes out/jobs/<index>.json; returns that record."""
    runner = runner or default_runner()
    j = job_at(study, index)
    record = {"study": study.name, "digest": study.digest(), "index": index,
              "problem": j["problem"], "kind": j["kind"], "label": j["label"],
              "assignment": j["assignment"], "ok": False, "report": None, "message": ""}
    if j["error"]:
        record["message"] = j["error"]
        _write_json(result_path(out, index), record)
        return record
    scene_path = os.path.join(out, "scenes", f"{index:05d}.json")
    _write_json(scene_path, j["scene"])
    cmd = [runner, scene_path]
    if j["samples"]:
        samples_path = os.path.join(out, "samples", f"{j['problem']}.json")
        if not os.path.exists(samples_path):
            _write_json(samples_path, {"points": j["samples"]})
        cmd += ["--samples", samples_path]
    start = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=study.timeout)
    except subprocess.TimeoutExpired:
        record["message"] = f"timed out after {study.timeout:g} s"
    else:
        record["exit"] = p.returncode
        if p.returncode == 0:
            try:
                record["report"] = json.loads(p.stdout)
                record["ok"] = True
            except json.JSONDecodeError as e:
                record["message"] = f"unreadable report: {e}"
        else:
            record["message"] = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else f"exit {p.returncode}"
    record["wall_s"] = time.monotonic() - start
    record["command"] = cmd
    _write_json(result_path(out, index), record)
    return record


def _done(study, out, index):
    try:
        with open(result_path(out, index)) as f:
            r = json.load(f)
        return r.get("digest") == study.digest()
    except (OSError, json.JSONDecodeError):
        return False


def _run_one(args):
    # A process pool worker: a fresh study per process keeps the workers independent.
    from .study import Study
    study_path, index, out, runner = args
    r = run_job(Study(study_path), index, out, runner)
    return index, r["ok"], r["label"], r["problem"], r["message"]


def run_all(study, out, runner=None, jobs=None, force=False, log=sys.stderr):
    """Runs every job not already done (same study digest) on `jobs` processes."""
    todo = [i for i in range(len(study.jobs)) if force or not _done(study, out, i)]
    jobs = max(1, jobs or os.cpu_count() or 1)
    print(f"polycut-study: {len(study.jobs)} jobs, {len(todo)} to run on {jobs} processes",
          file=log)
    args = [(study.path, i, out, runner or default_runner()) for i in todo]
    with concurrent.futures.ProcessPoolExecutor(max_workers=jobs) as pool:
        for index, ok, label, problem, message in pool.map(_run_one, args):
            status = "ok  " if ok else "FAIL"
            print(f"  [{index:3d}] {status} {problem}: {label}" + ("" if ok else f": {message}"),
                  file=log)
