"""A study file (docs/study.md) and its job list.

The job list is the single index -> configuration mapping every backend uses: the local process
pool, a Slurm array task (SLURM_ARRAY_TASK_ID) and a Kubernetes indexed job
(JOB_COMPLETION_INDEX) all call job(study, index). It is a pure function of the study file and
the base scenes it names, so every node computes the same list.
"""
import copy
import hashlib
import itertools
import json
import os

from . import axes as ax
from . import references

SCHEMA = os.path.join(os.path.dirname(__file__), "study.schema.json")


class StudyError(ValueError):
    """An invalid study file: the message names the file and the field."""


def _validate(doc, path):
    try:
        import jsonschema
    except ImportError:  # pragma: no cover - Debian's python3-jsonschema is in ./polycut
        return
    with open(SCHEMA) as f:
        schema = json.load(f)
    errors = sorted(jsonschema.Draft202012Validator(schema).iter_errors(doc), key=lambda e: list(e.path))
    if errors:
        e = errors[0]
        where = "/" + "/".join(str(p) for p in e.path)
        raise StudyError(f"{path}: {where}: {e.message}")


class Study:
    """A loaded study: its problems with merged axes, base scenes and the job list."""

    def __init__(self, path):
        self.path = os.path.abspath(path)
        self.directory = os.path.dirname(self.path)
        try:
            with open(self.path) as f:
                self.doc = json.load(f)
        except (OSError, json.JSONDecodeError) as e:
            raise StudyError(f"{path}: {e}") from None
        _validate(self.doc, path)
        self.name = self.doc["name"]
        self.cost = self.doc.get("cost", "step_ms")
        self.group_by = self.doc.get("group_by", ["method", "element"])
        self.timeout = self.doc.get("timeout", 1800)
        names = [p["name"] for p in self.doc["problems"]]
        if len(set(names)) != len(names):
            raise StudyError(f"{path}: /problems: problem names must be distinct")
        self.problems = [self._problem(i, p) for i, p in enumerate(self.doc["problems"])]
        self.jobs = []
        for problem in self.problems:
            self.jobs.extend(self._jobs_of(problem))
        for i, j in enumerate(self.jobs):
            j["index"] = i

    def _problem(self, i, p):
        where = f"{self.path}: /problems/{i}"
        scene_path = os.path.normpath(os.path.join(self.directory, p["scene"]))
        try:
            with open(scene_path) as f:
                base = json.load(f)
        except (OSError, json.JSONDecodeError) as e:
            raise StudyError(f"{where}/scene: {e}") from None
        # Files a scene names are relative to the scene: make them absolute, since the
        # materialized scenes live in the output directory.
        geo = base.get("geometry", {})
        if "path" in geo and not os.path.isabs(geo["path"]):
            geo["path"] = os.path.normpath(os.path.join(os.path.dirname(scene_path), geo["path"]))
        ax.merge_patch(base, p.get("set", {}))
        if "steps" in p:
            base.setdefault("output", {})["steps"] = p["steps"]
        axes = dict(self.doc.get("axes", {}))
        axes.update(p.get("axes", {}))
        ref = p["reference"]
        if ("analytic" in ref) == ("converged" in ref):
            raise StudyError(f"{where}/reference: needs exactly one of \"analytic\" or \"converged\"")
        if "analytic" in ref:
            references.check_analytic(ref, base, f"{where}/reference")
        return {
            "name": p["name"],
            "description": p.get("description", ""),
            "scene_path": scene_path,
            "base": base,
            "axes": axes,
            "exclude": self.doc.get("exclude", []) + p.get("exclude", []),
            "duration": p.get("duration", ax.base_duration(base)),
            "reference": ref,
            "group_by": p.get("group_by", self.group_by),
            "samples": references.sample_points(ref, base, f"{where}/reference")
            if "converged" in ref else None,
        }

    def _job(self, problem, kind, assignment):
        try:
            scene = ax.apply(problem["base"], assignment, problem["duration"])
        except ax.AxisError as e:
            scene, error = None, str(e)
        else:
            error = None
            scene["name"] = f"{problem['name']}-{kind}"
        return {
            "problem": problem["name"],
            "kind": kind,
            "assignment": assignment,
            "label": "reference" if kind == "reference" else ax.label(assignment),
            "scene": scene,
            "error": error,
            "samples": problem["samples"],
        }

    def _jobs_of(self, problem):
        jobs = []
        if "converged" in problem["reference"]:
            jobs.append(self._job(problem, "reference", dict(problem["reference"]["converged"])))
        names = list(problem["axes"])
        for values in itertools.product(*(problem["axes"][n] for n in names)):
            assignment = dict(zip(names, values))
            if any(all(assignment.get(k) == v for k, v in ex.items()) for ex in problem["exclude"]):
                continue
            jobs.append(self._job(problem, "run", assignment))
        return jobs

    def problem(self, name):
        return next(p for p in self.problems if p["name"] == name)

    def digest(self):
        """Hash of the job list: results of another version of the study are not mixed in."""
        text = json.dumps([[j["problem"], j["kind"], j["assignment"], j["scene"]] for j in self.jobs],
                          sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


def job(study, index):
    """The configuration of job `index` (0-based): the one mapping of every backend."""
    if not (0 <= index < len(study.jobs)):
        raise StudyError(f"{study.path}: job index {index} outside [0, {len(study.jobs) - 1}]")
    return copy.deepcopy(study.jobs[index])


def index_from_environment(env=None):
    """The array index a cluster scheduler gives a task: Slurm's SLURM_ARRAY_TASK_ID or
    Kubernetes' JOB_COMPLETION_INDEX (None when neither is set)."""
    env = os.environ if env is None else env
    for key in ("SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"):
        if env.get(key, "") != "":
            return int(env[key])
    return None
