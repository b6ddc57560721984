"""Cluster plans of a study (docs/study.md, "On a cluster"): a Slurm job array script and a
Kubernetes Indexed Job manifest. Both run the same command per index,
    polycut-study run-one STUDY --out DIR
which reads its index from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX (study.job(), the mapping
the local pool uses too), then a final `polycut-study collect` writes the table and plots."""
import os
import shlex


def _max_threads(study):
    t = 1
    for j in study.jobs:
        if j["scene"]:
            t = max(t, int(j["scene"].get("integrator", {}).get("threads", 1)))
    return t


def slurm(study, out, tool, time_limit="01:00:00", memory="4G", partition=None):
    """An sbatch script running every job as one task of an array; returns its text."""
    n = len(study.jobs)
    q = shlex.quote
    lines = [
        "#!/bin/bash",
        f"# polycut trade study {study.name}: {n} jobs, one per array task (docs/study.md).",
        f"# Submit: jid=$(sbatch --parsable {q(os.path.join(out, 'plan', 'study.sbatch'))})",
        f"# then:   sbatch --dependency=afterok:$jid {q(os.path.join(out, 'plan', 'collect.sbatch'))}",
        f"#SBATCH --job-name=polycut-study-{study.name}",
        f"#SBATCH --array=0-{n - 1}",
        f"#SBATCH --cpus-per-task={_max_threads(study)}",
        f"#SBATCH --time={time_limit}",
        f"#SBATCH --mem={memory}",
        f"#SBATCH --output={os.path.join(out, 'logs', '%A_%a.out')}",
    ]
    if partition:
        lines.append(f"#SBATCH --partition={partition}")
    lines += ["set -euo pipefail",
              f"exec {q(tool)} run-one {q(study.path)} --out {q(out)}", ""]
    return "\n".join(lines)


def slurm_collect(study, out, tool):
    q = shlex.quote
    return "\n".join([
        "#!/bin/bash",
        f"#SBATCH --job-name=polycut-study-{study.name}-collect",
        "#SBATCH --cpus-per-task=1",
        f"#SBATCH --output={os.path.join(out, 'logs', 'collect_%j.out')}",
        "set -euo pipefail",
        f"exec {q(tool)} collect {q(study.path)} --out {q(out)}", ""])


def kubernetes(study, out, tool, image="polycut:latest", claim="polycut-study", parallelism=8):
    """A batch/v1 Indexed Job manifest (YAML text): completions = the job count; each pod runs
    one index (JOB_COMPLETION_INDEX) with the study and output on a shared volume claim."""
    n = len(study.jobs)
    threads = _max_threads(study)
    name = f"polycut-study-{study.name}".lower().replace("_", "-").replace(".", "-")[:52]
    mount = os.path.commonpath([os.path.dirname(study.path), out])
    if mount == os.sep:
        raise ValueError(f"the study ({study.path}) and the output ({out}) share no directory "
                         "to mount from the volume claim: put both under one")
    return f"""# polycut trade study {study.name}: {n} jobs as a Kubernetes Indexed Job (docs/study.md).
# kubectl apply -f {os.path.join(out, 'plan', 'study-job.yaml')}
# kubectl wait --for=condition=complete job/{name} --timeout=24h
# then collect: {tool} collect {study.path} --out {out}   (in a pod with the same volume)
apiVersion: batch/v1
kind: Job
metadata:
  name: {name}
spec:
  completionMode: Indexed
  completions: {n}
  parallelism: {min(parallelism, n)}
  backoffLimitPerIndex: 1
  template:
    spec:
      restartPolicy: Never
      containers:
      - name: run
        image: {image}
        command: ["{tool}", "run-one", "{study.path}", "--out", "{out}"]
        resources:
          requests:
            cpu: "{threads}"
          limits:
            cpu: "{threads}"
        volumeMounts:
        - name: study
          mountPath: {mount}
      volumes:
      - name: study
        persistentVolumeClaim:
          claimName: {claim}
"""


def gnu_parallel(study, out, tool, jobs=None):
    """The same job list for GNU parallel on one machine (an alternative to `run`)."""
    q = shlex.quote
    j = f"-j {jobs} " if jobs else ""
    return (f"seq 0 {len(study.jobs) - 1} | parallel {j}--halt never "
            f"{q(tool)} run-one {q(study.path)} --out {q(out)} --index {{}}\n"
            f"{q(tool)} collect {q(study.path)} --out {q(out)}\n")
