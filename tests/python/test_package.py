#!/usr/bin/python3
"""The installable Python package clients/python (issue 16 item 5): `pip install` works offline
into a venv that sees Debian's python3-zmq and python3-numpy, and the installed package drives a
LocalServer through typed results, a SurfaceMirror equal to get_surface, an RpcError with the
field's pointer, and stops the server cleanly; every public name has a docstring.

    test_package.py POLYCUT_SERVER SOURCE_DIR
"""
import inspect
import os
import shutil
import subprocess
import sys
import tempfile

CHECK = r'''
import inspect, sys, time
import numpy as np
import polycut

assert "site-packages" in polycut.__file__, polycut.__file__   # the installed copy
server_exe = sys.argv[1]
sys.path.insert(0, sys.argv[2])
from test_python_client import SCENE as scene  # the small block of the older client's test
# Every public class and method documented.
for name in polycut.__all__:
    obj = getattr(polycut, name)
    assert inspect.getdoc(obj), f"{name} has no docstring"
for meth in ("request", "call", "notify", "hello", "load_scene", "cut", "scalpel", "end_stroke",
             "get_surface", "grab", "move_grab", "apply_force", "surface_mirror"):
    assert inspect.getdoc(getattr(polycut.Client, meth)), f"Client.{meth} has no docstring"

server = polycut.LocalServer(executable=server_exe)
with server:
    with server.client(timeout_ms=20000) as c:
        hello = c.hello()
        assert isinstance(hello, polycut.Hello) and hello.protocol == "polycut/1", hello
        assert hello.stream == server.stream, (hello.stream, server.stream)
        info = c.load_scene(scene=scene)
        assert isinstance(info, polycut.SceneInfo) and info.cell_count == 192, info
        mirror = c.surface_mirror()
        time.sleep(0.3)
        grab = c.grab([0.015, 0.015, 0.02], stiffness=300)
        assert isinstance(grab, int), grab
        deadline = time.time() + 5  # the grab is applied at the next tick boundary
        while c.get_stats().grabs != 1 and time.time() < deadline:
            time.sleep(0.02)
        assert c.get_stats().grabs == 1
        c.move_grab(grab, [0.015, 0.015, 0.025])
        c.release(grab)
        tris = np.array([[[-0.012, 0.003, 0.03], [-0.012, 0.003, 0.008], [0.012, 0.003, 0.03]],
                         [[-0.012, 0.003, 0.008], [0.012, 0.003, 0.008], [0.012, 0.003, 0.03]]])
        cut = c.cut(tris)
        assert isinstance(cut, polycut.CutResult), cut
        assert cut.triangles == 2 and cut.topology_version > info.topology_version, cut
        while mirror.header["tick"] < cut.tick:  # the first frame that shows the cut
            assert mirror.update(timeout_ms=2000) > 0, "stream stalled"
        paused = c.pause()
        assert isinstance(paused, polycut.RunState) and not paused.running, paused
        while mirror.header["tick"] < paused.tick:
            assert mirror.update(timeout_ms=2000) > 0, "stream stalled"
        surface = c.get_surface()
        assert isinstance(surface, polycut.Surface)
        assert mirror.header["seq"] == surface.seq, (mirror.header["seq"], surface.seq)
        assert np.array_equal(mirror.positions, surface.positions)
        assert np.array_equal(mirror.tags, surface.tags), (mirror.tags.shape, surface.tags.shape)
        assert surface.cut_triangles > 0, (surface.header, cut)
        stats = c.get_stats()
        assert stats.grabs == 0 and stats.topology_version == surface.header["topology_version"]
        try:
            c.grab([0, 0], stiffness=100.0)
            raise AssertionError("a 2-vector point was accepted")
        except polycut.RpcError as e:
            assert e.code == -32602 and e.pointer == "/params/point", e
        mirror.close()
status = server.process.returncode
assert status == 0, f"server exit status {status}"
print("package checks passed")
'''


def main():
    server_exe, source = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        # A copy: pip builds in the tree it is given (build/, *.egg-info).
        src = os.path.join(tmp, "src")
        shutil.copytree(os.path.join(source, "clients", "python"), src,
                        ignore=shutil.ignore_patterns("__pycache__", "build", "*.egg-info"))
        venv = os.path.join(tmp, "venv")
        subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", venv],
                       check=True)
        python = os.path.join(venv, "bin", "python")
        # Build isolation on and no index: the in-tree backend needs nothing from one.
        install = subprocess.run([python, "-m", "pip", "install", "--no-index",
                                  "--quiet", "--disable-pip-version-check", src],
                                 capture_output=True, text=True)
        if install.returncode != 0:
            print("FAIL: pip install offline:", install.stdout, install.stderr)
            failures += 1
        else:
            print("ok   pip install ./clients/python offline (no index, no build isolation)")
            run = subprocess.run([python, "-c", CHECK, server_exe,
                                  os.path.join(source, "tests", "server")], cwd=tmp)
            if run.returncode != 0:
                print("FAIL: the installed package")
                failures += 1
            else:
                print("ok   the installed package drives a LocalServer")
    print(f"{2 - failures} passed, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
