#!/usr/bin/python3
"""A notebook-style tour of the polycut Python package (cells marked ``# %%`` run one by one in
Jupyter, VS Code or Spyder, or all at once as a script).

    /usr/bin/python3 clients/python/examples/notebook.py [--server PATH] [--plot out.png]

It starts a local server on the default scene, watches the block sag, cuts it with a scripted
scalpel stroke, pulls one side open with a grab, and plots the tip's sag and the cut with
matplotlib.
"""
# %% Set-up: the package from this source tree if it is not installed.
import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
try:
    import polycut
except ImportError:
    sys.path.insert(0, os.path.dirname(HERE))
    import polycut

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--server", help="polycut-server executable (default: see find_server)")
parser.add_argument("--plot", help="write the figure to this PNG")
args, _ = parser.parse_known_args()
scene = os.path.join(HERE, "..", "..", "..", "assets", "scenes", "default.json")

# %% Start a server; the context manager stops it at the end.
server = polycut.LocalServer(scene=scene, paused=True, executable=args.server).start()
c = server.client()
hello = c.hello()
print(f"{hello.server}, protocol {hello.protocol}, scene {hello.scene}")

# %% Follow the surface while the block sags under gravity (60 ticks = 1 s).
mirror = c.surface_mirror()
top = int(np.argmax(mirror.positions[:, 2]))  # a vertex on the top face
sag = []
for _ in range(60):
    c.step(1)
    mirror.update(timeout_ms=1000)
    sag.append(float(mirror.positions[top, 2]))
print(f"top vertex: z {sag[0] * 1e3:.3f} -> {sag[-1] * 1e3:.3f} mm after {mirror.header['tick']} ticks")

# %% Cut with a scalpel stroke across the block (blade 4 cm deep, moved 2 mm per sample).
c.resume()
for k, y in enumerate(np.linspace(-0.07, 0.07, 71)):
    c.scalpel(stroke=1, a=[0.003, y, 0.07], b=[0.003, y, 0.03], wait=True)
result = c.end_stroke(stroke=1)
print(f"cut: topology version {result.topology_version}, {result.triangles} sweep triangles")

# %% Pull one side open with a grab.
grab = c.grab(point=[0.02, 0.0, 0.05], stiffness=400)
for k in range(30):
    c.move_grab(grab, target=[0.02 + 0.0005 * k, 0.0, 0.05 + 0.0005 * k])
    time.sleep(1 / 60)
mirror.update(timeout_ms=500)
stats = c.get_stats()
print(f"{mirror.tags.size} triangles, {int((mirror.tags == 2).sum())} on the cut; "
      f"step p50 {stats.step_ms_p50:.2f} ms, p99 {stats.step_ms_p99:.2f} ms")
c.release(grab)

# %% Plot: the sag over time and the cut surface seen from the side.
if args.plot:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    a.plot(np.arange(len(sag)) / 60.0, (np.array(sag) - sag[0]) * 1e3)
    a.set_xlabel("time [s]")
    a.set_ylabel("top vertex z change [mm]")
    a.grid(True, alpha=0.3)
    cut = mirror.triangles[mirror.tags == 2]
    centres = mirror.positions[cut].mean(axis=1)
    b.scatter(centres[:, 1] * 1e3, centres[:, 2] * 1e3, s=4, c=centres[:, 0] * 1e3, cmap="viridis")
    b.set_xlabel("y [mm]")
    b.set_ylabel("z [mm]")
    b.set_title("cut triangles seen along x (colour: x [mm])")
    b.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.plot, dpi=100)
    print("figure:", args.plot)

# %% Stop the server.
mirror.close()
c.close()
print("server exit status", server.stop())
