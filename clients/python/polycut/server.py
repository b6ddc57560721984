"""A local polycut-server for scripts and notebooks, started and stopped by a context manager."""
import json
import os
import shutil
import subprocess

from .client import Client


def find_server(executable=None):
    """The polycut-server executable: `executable`, else $POLYCUT_SERVER, else ``polycut-server``
    on PATH, else the release build of the source tree this package sits in."""
    candidates = [executable, os.environ.get("POLYCUT_SERVER"), shutil.which("polycut-server"),
                  os.path.join(os.path.dirname(__file__), "..", "..", "..", "build", "release",
                               "server", "polycut-server")]
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return os.path.abspath(c)
    raise FileNotFoundError("polycut-server not found: pass executable=, set POLYCUT_SERVER or "
                            "put it on PATH (./polycut build makes build/release/server/)")


class LocalServer:
    """Starts ``polycut-server`` on free loopback ports and stops it on exit.

        with polycut.LocalServer(scene="assets/scenes/default.json") as server:
            with server.client() as c:
                c.get_stats()

    :param scene: scene file to start with (None: the server's default)
    :param scene_dir: directory of scenes ``load_scene`` finds by name
    :param rate_hz: tick rate [Hz]; :param paused: start paused (step with ``Client.step``)
    :param executable: the server binary (see :func:`find_server`)
    :param extra_args: more command-line arguments

    ``control`` and ``stream`` are the bound endpoints once started.
    """

    def __init__(self, scene=None, scene_dir=None, rate_hz=None, paused=False, executable=None,
                 extra_args=(), startup_timeout_s=60):
        self.args = [find_server(executable), "--control", "tcp://127.0.0.1:*",
                     "--stream", "tcp://127.0.0.1:*", "--quiet"]
        if scene:
            self.args += ["--scene", os.fspath(scene)]
        if scene_dir:
            self.args += ["--scene-dir", os.fspath(scene_dir)]
        if rate_hz:
            self.args += ["--rate", str(rate_hz)]
        if paused:
            self.args.append("--paused")
        self.args += list(extra_args)
        self.startup_timeout_s = startup_timeout_s
        self.process = None
        self.control = self.stream = None

    def start(self):
        """Starts the server and waits for its endpoints (its first stdout line)."""
        self.process = subprocess.Popen(self.args, stdout=subprocess.PIPE, text=True)
        line = self.process.stdout.readline()
        if not line:
            code = self.process.wait(timeout=self.startup_timeout_s)
            raise RuntimeError(f"polycut-server exited with status {code} before it listened")
        ready = json.loads(line)
        self.control, self.stream = ready["control"], ready["stream"]
        return self

    def client(self, **kwargs):
        """A :class:`~polycut.Client` connected to this server."""
        return Client(self.control, **kwargs)

    def stop(self, timeout_s=20):
        """Asks the server to shut down, then waits; kills it if it does not stop in time.
        Returns its exit status."""
        if self.process is None or self.process.poll() is not None:
            return None if self.process is None else self.process.returncode
        try:
            with Client(self.control, timeout_ms=int(timeout_s * 1000)) as c:
                c.shutdown()
            return self.process.wait(timeout=timeout_s)
        except Exception:
            self.process.kill()
            return self.process.wait()
        finally:
            self.process.stdout.close()

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()
