"""In-tree PEP 517 build backend of the polycut package.

pip builds a package in an isolated environment and first installs the backend named in
pyproject.toml there; setuptools would have to come from an index, so `pip install
./clients/python` fails on a machine without network access. The package is pure Python (one
directory of modules), so this backend needs nothing but the standard library: it writes the
wheel (PEP 427) and its metadata (core metadata 2.1) from the [project] table itself. Editable
installs are not supported (use PYTHONPATH=clients/python for development).
"""
import base64
import hashlib
import io
import os
import tomllib
import zipfile

_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_PACKAGE = "polycut"


def _project():
    with open(os.path.join(_ROOT, "pyproject.toml"), "rb") as f:
        return tomllib.load(f)["project"]


def _dist_info(p):
    return f"{p['name']}-{p['version']}.dist-info"


def _wheel_name(p):
    return f"{p['name']}-{p['version']}-py3-none-any.whl"


def _metadata(p):
    lines = ["Metadata-Version: 2.1", f"Name: {p['name']}", f"Version: {p['version']}",
             f"Summary: {p.get('description', '')}"]
    if "requires-python" in p:
        lines.append(f"Requires-Python: {p['requires-python']}")
    lines += [f"Requires-Dist: {d}" for d in p.get("dependencies", [])]
    readme = p.get("readme")
    body = ""
    if readme:
        lines.append("Description-Content-Type: text/markdown")
        with open(os.path.join(_ROOT, readme), encoding="utf-8") as f:
            body = "\n" + f.read()
    return "\n".join(lines) + "\n" + body


_WHEEL = "Wheel-Version: 1.0\nGenerator: polycut_backend\nRoot-Is-Purelib: true\nTag: py3-none-any\n"


def _record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    p = _project()
    d = os.path.join(metadata_directory, _dist_info(p))
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "METADATA"), "w", encoding="utf-8") as f:
        f.write(_metadata(p))
    with open(os.path.join(d, "WHEEL"), "w", encoding="utf-8") as f:
        f.write(_WHEEL)
    return _dist_info(p)


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    p = _project()
    files = []  # (archive name, bytes)
    package_dir = os.path.join(_ROOT, _PACKAGE)
    for dirpath, dirnames, filenames in os.walk(package_dir):
        dirnames[:] = sorted(d for d in dirnames if d != "__pycache__")
        for name in sorted(filenames):
            if name.endswith((".pyc", ".pyo")):
                continue
            path = os.path.join(dirpath, name)
            with open(path, "rb") as f:
                files.append((os.path.relpath(path, _ROOT).replace(os.sep, "/"), f.read()))
    info = _dist_info(p)
    files.append((f"{info}/METADATA", _metadata(p).encode()))
    files.append((f"{info}/WHEEL", _WHEEL.encode()))
    record = [_record_line(n, d) for n, d in files] + [f"{info}/RECORD,,"]
    files.append((f"{info}/RECORD", ("\n".join(record) + "\n").encode()))
    os.makedirs(wheel_directory, exist_ok=True)
    target = os.path.join(wheel_directory, _wheel_name(p))
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in files:
            z.writestr(zipfile.ZipInfo(name, date_time=(2026, 1, 1, 0, 0, 0)), data,
                       compress_type=zipfile.ZIP_DEFLATED)
    return os.path.basename(target)


def build_sdist(sdist_directory, config_settings=None):
    import tarfile
    p = _project()
    base = f"{p['name']}-{p['version']}"
    os.makedirs(sdist_directory, exist_ok=True)
    target = os.path.join(sdist_directory, base + ".tar.gz")
    with tarfile.open(target, "w:gz") as t:
        for rel in ["pyproject.toml", p.get("readme", "README.md"), "_build", _PACKAGE]:
            t.add(os.path.join(_ROOT, rel), arcname=f"{base}/{rel}",
                  filter=lambda ti: None if "__pycache__" in ti.name else ti)
    return os.path.basename(target)
