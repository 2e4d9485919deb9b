#!/usr/bin/env python3
"""rollstack beside the engines a user would pick instead: MuJoCo and PyBullet.

    scripts/peers.py [BIN] [--repeat N] [--scenes NAME,...] [--engines NAME,...]
                     [--json | --markdown] [--smoke]

Builds the same 2D block scenes in each engine (same sizes, masses, gravity, μ, Δt and
number of steps as rollstack's commands), runs them one thread each, interleaved (every
repeat runs every scene in every engine before the next repeat), and prints per scene
and engine: µs per step (median over the repeats), the deepest interpenetration over
the run and the outcome (which blocks fell, which reached the floor, and the run's
failure, as rollstack defines them: docs/cli.md, `blocks run`, the JSON keys `events`
and `failure`). BIN is the rollstack binary (default target/release/rollstack).

Not part of CI: no test runs it. `--smoke` runs one scene for a few steps, once, to
check that the script and the engines work. Needs Python 3, numpy and the engines from
pip (`pip install mujoco pybullet numpy`); an engine that is not installed is named in
the output and left out. docs/peers.md has a measured table and how to read it.

How each engine holds the scene:
- A block is a box w × h in the x–z plane (x right, z up: rollstack's y), as deep (along
  y) as the narrowest block is wide, with mass m and the moment of inertia m(w² + h²)/12
  about y that rollstack uses; three joints (slide x, slide z, hinge about −y, so that
  the angle is rollstack's counterclockwise θ) keep it in the plane.
- A shaken base is a box on a slide joint along x, 10⁶ times heavier than all blocks
  together, whose position and velocity are set to x = A sin ωt, v = Aω cos ωt before
  every step: a kinematic base whose velocity the contacts see. A fixed base (the Lire
  table) is a static box. The floor is a plane; the base and the floor do not collide.
- Every contact has rollstack's μ; every other contact and solver setting is the
  engine's default (the output lists them), with no restitution and no joint damping.
- Time: the step is timed (for a shaken base, with setting the base's state before it);
  reading the poses after it, for the measures below, is not. rollstack's time is its
  JSON `wall_time_s` (solver time, without start-up and I/O) over its steps.

The measures are computed the same way for every engine from the poses after each step
(for rollstack from its `trajectory.csv`, and checked against its own JSON):
interpenetration is the deepest overlap of any two bodies, the smallest translation
along a face normal that separates two rectangles, or a corner below the floor;
the events are rollstack's: a block lost its support on the body beneath (faces turned
from each other, its centre below the lower top face, or the faces no longer
overlapping; not rollstack's test for a corner that entered from the side), a block
tilted past atan(w/h), a block touched the floor, the column's top fell by more than
a block height. A block *fell* when it lost its support or tipped (rollstack's
`blocks explore` outcome); the failure is the first event of any kind.
"""
import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field

# One thread each, set before numpy or an engine loads its thread pool.
for _var in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS", "RAYON_NUM_THREADS"):
    os.environ[_var] = "1"

import numpy as np  # noqa: E402

# rollstack's tolerance for a contact that touches: 1e-6 of the smallest block height
# (blockstack::simulation::OPEN_GAP_TOL), used for "touched the floor".
OPEN_GAP_TOL = 1e-6
# The shaken base's mass over all blocks' mass: heavy enough that the contacts do not
# move it within a step, its state being set before every step.
BASE_MASS_RATIO = 1e6
# The Lire tower's bottom block is pushed out by this share of its width (--perturb bottom).
LIRE_PERTURBATION = 0.01


@dataclass
class Box:
    """A rectangle w × h with mass m, its centre (x, y) and angle θ at t = 0."""

    width: float
    height: float
    mass: float = 1.0
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0


@dataclass
class Scene:
    """One benchmark scene: its geometry, and the rollstack command that runs it."""

    name: str
    label: str
    base: Box
    blocks: list
    floor: float  # y of the floor
    amplitude: float  # base x = amplitude sin(omega t); 0: a fixed base
    omega: float
    args: list  # the rollstack command, without the binary
    # From rollstack's JSON (`scene`): filled by the first rollstack run.
    mu: float = float("nan")
    gravity: float = float("nan")
    dt: float = float("nan")
    steps: int = 0
    settings: dict = field(default_factory=dict)

    def base_x(self, t):
        return self.amplitude * math.sin(self.omega * t)

    def base_v(self, t):
        return self.amplitude * self.omega * math.cos(self.omega * t)

    def sizes(self):
        """(w, h) per body, the base first."""
        return np.array([(b.width, b.height) for b in [self.base] + self.blocks])


def column(name, n, omega, amplitude, mu, steps_per_period, t_end):
    """`rollstack blocks shake`: n blocks 0.2 × 0.4 on a base 1 × 0.1 shaken as
    x = A sin ωt, from rest, a floor at the base's bottom (docs/cli.md)."""
    w, h, base = 0.2, 0.4, Box(1.0, 0.1)
    blocks = [Box(w, h, y=base.height / 2 + h / 2 + k * h) for k in range(n)]
    args = ["blocks", "shake", "--blocks", str(n), "--omega", f"{omega}",
            "--amplitude", f"{amplitude}", "--mu", f"{mu}",
            "--steps-per-period", f"{steps_per_period}", "--t-end", f"{t_end}",
            "--width", f"{w}", "--height", f"{h}"]
    label = (f"{n}-block column, base x = {amplitude} sin {omega}t, mu = {mu}, "
             f"{steps_per_period} steps per period, t_end = {t_end}")
    return Scene(name, label, base, blocks, -base.height / 2, amplitude, omega, args)


def lire(name, n):
    """`rollstack blocks lire --perturb bottom --floor`: n blocks 1 × 0.2 at the harmonic
    maximum overhang on a fixed table 1 × 0.2, the bottom block pushed out by 1 % of its
    width, a floor at the table's bottom (docs/scenes.md, `lire-collapse`)."""
    w, h, base = 1.0, 0.2, Box(1.0, 0.2)
    edge, blocks = w / 2, []
    for k in range(1, n + 1):
        edge += w / (2 * (n - k + 1))  # the harmonic overhangs, ERRATA 16
        blocks.append(Box(w, h, x=edge - w / 2, y=base.height / 2 + h / 2 + (k - 1) * h))
    blocks[0].x += LIRE_PERTURBATION * w
    args = ["blocks", "lire", "--blocks", str(n), "--perturb", "bottom", "--floor"]
    label = f"{n}-block Lire tower collapsing onto a floor (--perturb bottom --floor)"
    return Scene(name, label, base, blocks, -base.height / 2, 0.0, 0.0, args)


def scenes(smoke):
    if smoke:
        return [column("column10", 10, 2, 0.001, 0.2, 314, 0.05)]
    return [
        column("column10", 10, 2, 0.001, 0.2, 314, 1),
        column("shaken6", 6, 2, 0.2, 0.3, 200, 20),
        lire("lire10", 10),
        column("column100", 100, 2, 0.001, 0.2, 314, 0.3),
    ]


# ---------------------------------------------------------------------------------------
# Geometry of the rectangles: interpenetration and rollstack's failure events.


def frames(poses):
    """Per body (rows of x, y, θ): centre, e1 and e2."""
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    return poses[:, :2], np.stack([c, s], 1), np.stack([-s, c], 1)


def corners(poses, sizes):
    """The four corners of each body, shape (bodies, 4, 2)."""
    r, e1, e2 = frames(poses)
    signs = np.array([(-1, -1), (1, -1), (1, 1), (-1, 1)]) / 2
    u = signs[None, :, 0:1] * sizes[:, None, 0:1]
    v = signs[None, :, 1:2] * sizes[:, None, 1:2]
    return r[:, None, :] + u * e1[:, None, :] + v * e2[:, None, :]


def deepest_overlap(poses, sizes, pairs, floor):
    """The deepest overlap of the bodies at these poses (blockstack::overlap): per pair,
    the smallest overlap of their projections on the four face normals (negative: a
    gap), and each block's lowest corner below the floor. Returns (depth, i, j), j = -1
    for the floor."""
    cs = corners(poses, sizes)
    _, e1, e2 = frames(poses)
    i, j = pairs[:, 0], pairs[:, 1]
    axes = np.stack([e1[i], e2[i], e1[j], e2[j]], 1)  # (pairs, 4, 2)
    pa = np.einsum("pkd,pcd->pkc", axes, cs[i])
    pb = np.einsum("pkd,pcd->pkc", axes, cs[j])
    overlap = np.minimum(pa.max(2), pb.max(2)) - np.maximum(pa.min(2), pb.min(2))
    depth = overlap.min(1)
    best = int(depth.argmax())
    result = (float(depth[best]), int(i[best]), int(j[best]))
    below = -floor_gaps(poses, sizes, floor)
    k = int(below.argmax())
    if below[k] > result[0]:
        result = (float(below[k]), k + 1, -1)
    return result


def supported(lower, upper, lsize, usize):
    """Whether `lower` (x, y, θ) supports `upper` (blockstack::interface, the support
    test (G.2.4) as corrected by ERRATA 23)."""
    both = np.array([lower, upper])
    (rl, ru), (e1l, _), (e2l, e2u) = frames(both)
    if e2l @ e2u <= 0:
        return False  # turned over
    if (ru - rl) @ e2l <= lsize[1] / 2:
        return False  # its centre below the lower top face
    bottom = corners(both, np.array([lsize, usize]))[1, :2]  # the upper's bottom corners
    along = (bottom - rl) @ e1l
    # Faces that no longer overlap: it slid or fell off. rollstack's fourth case, a
    # corner that entered from the side (Support::Sunk), is left out: it tells a corner
    # 10⁻⁶ deep at a face's edge from a resting one, and every corner of the peers'
    # columns rests 10⁻⁴ deep.
    return along.max() > -lsize[0] / 2 and along.min() < lsize[0] / 2


def half_heights(poses, sizes):
    """Per block, how far its corners reach above and below its centre."""
    th = poses[1:, 2]
    return 0.5 * sizes[1:, 0] * np.abs(np.sin(th)) + 0.5 * sizes[1:, 1] * np.abs(np.cos(th))


def column_top(poses, sizes):
    """The highest corner of any block."""
    return float((poses[1:, 1] + half_heights(poses, sizes)).max())


def floor_gaps(poses, sizes, floor):
    """Per block, the height of its lowest corner above the floor."""
    return poses[1:, 1] - half_heights(poses, sizes) - floor


def events(scene, times, states):
    """rollstack's failure events (blockstack::events) of the states (steps, bodies, 3),
    the base first, in the order they happened: dicts with kind, t and block (1-based)."""
    sizes = scene.sizes()
    n = len(scene.blocks)
    tipping = np.arctan2(sizes[1:, 0], sizes[1:, 1])
    floor_tol = OPEN_GAP_TOL * sizes[1:, 1].min()
    drop = sizes[1:, 1].min()
    first = states[0]
    top0 = column_top(first, sizes)
    seen = set()
    # Support is lost only by a block that had it; a block on the floor at the start
    # does not touch it later.
    for k in range(n):
        if not supported(first[k], first[k + 1], sizes[k], sizes[k + 1]):
            seen.add(("support_lost", k + 1))
    for k in np.nonzero(floor_gaps(first, sizes, scene.floor) <= floor_tol)[0]:
        seen.add(("touched_floor", int(k) + 1))
    out = []

    def record(kind, block, t):
        if (kind, block) not in seen:
            seen.add((kind, block))
            out.append({"kind": kind, "t": float(t), "block": block})

    for t, q in zip(times[1:], states[1:]):
        for k in range(n):
            if ("support_lost", k + 1) not in seen and not supported(
                    q[k], q[k + 1], sizes[k], sizes[k + 1]):
                record("support_lost", k + 1, t)
        tilt = np.abs(np.arctan2(np.sin(q[1:, 2]), np.cos(q[1:, 2])))
        for k in np.nonzero(tilt > tipping)[0]:
            record("tipped", int(k) + 1, t)
        for k in np.nonzero(floor_gaps(q, sizes, scene.floor) <= floor_tol)[0]:
            record("touched_floor", int(k) + 1, t)
        if column_top(q, sizes) < top0 - drop:
            record("height_dropped", None, t)
    return out


def outcome(evs):
    """What a user reads from the events (blockstack::exploration::Outcome): the blocks
    that fell (lost their support or tipped) in order, those on the floor, the failure
    (the first event of any kind)."""
    fell, on_floor = [], []
    for e in evs:
        k = e["block"]
        if e["kind"] in ("support_lost", "tipped") and k not in fell:
            fell.append(k)
        if e["kind"] == "touched_floor" and k not in on_floor:
            on_floor.append(k)
    return {"failure": evs[0] if evs else None, "fell": fell, "on_floor": sorted(on_floor)}


def measures(scene, times, states):
    """Interpenetration and outcome of a run, from its states (steps, bodies, 3)."""
    sizes = scene.sizes()
    m = len(sizes)
    pairs = np.array([(i, j) for i in range(m) for j in range(i + 1, m)])
    deepest = (-math.inf, 0, 0, 0.0)
    for t, q in zip(times, states):
        d, i, j = deepest_overlap(q, sizes, pairs, scene.floor)
        if d > deepest[0]:
            deepest = (d, i, j, float(t))
    def names(b):
        return "the floor" if b < 0 else ("the base" if b == 0 else f"block {b}")

    return {
        "max_penetration": max(deepest[0], 0.0),
        "penetration": {"t": deepest[3], "depth": deepest[0],
                        "first": names(deepest[1]), "second": names(deepest[2])},
        "outcome": outcome(events(scene, times, states)),
    }


# ---------------------------------------------------------------------------------------
# The engines. Each run returns (seconds per step, times, states).


def initial_state(scene):
    return np.array([[b.x, b.y, b.theta] for b in scene.blocks])


def rollstack_run(binary, scene, out=None):
    """One rollstack run: its JSON, and with `out` its trajectory.csv (the reference
    run). rollstack's own solver time, over the steps it took."""
    cmd = [binary] + scene.args + ["--json", "--force"]
    if out:
        cmd += ["--out", out, "--max-frames", "0"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if not proc.stdout.strip():
        raise RuntimeError(f"{' '.join(cmd)}: {proc.stderr.strip()}")
    report = json.loads(proc.stdout)
    if report.get("error"):
        raise RuntimeError(f"{' '.join(cmd)}: {report['error']}")
    return report


def rollstack_states(scene, path):
    """Times and states (base first) of rollstack's trajectory.csv."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    n = len(scene.blocks)
    states = np.zeros((len(data), n + 1, 3))
    states[:, 0, 0] = data["base_x"]
    for k in range(1, n + 1):
        states[:, k] = np.stack([data[f"x{k}"], data[f"y{k}"], data[f"theta{k}"]], 1)
    return data["t"], states


def mujoco_xml(scene):
    depth = min(b.width for b in scene.blocks)
    def box(b):
        return f'type="box" size="{b.width / 2!r} {depth / 2!r} {b.height / 2!r}"'

    mu = f'friction="{scene.mu!r} 0.005 0.0001"'  # MuJoCo's default torsional and rolling
    parts = [f'<mujoco><option timestep="{scene.dt!r}" gravity="0 0 {-scene.gravity!r}"/>',
             "<worldbody>",
             f'<geom name="floor" type="plane" pos="0 0 {scene.floor!r}" size="0 0 1" {mu}/>']
    if scene.amplitude:
        mass = BASE_MASS_RATIO * sum(b.mass for b in scene.blocks)
        parts.append(f'<body name="base"><joint name="base" type="slide" axis="1 0 0"/>'
                     f'<geom {box(scene.base)} mass="{mass!r}" {mu}/></body>')
    else:
        parts.append(f'<geom name="base" {box(scene.base)} {mu}/>')
    for k, b in enumerate(scene.blocks):
        parts.append(f'<body name="b{k}"><joint type="slide" axis="1 0 0"/>'
                     f'<joint type="slide" axis="0 0 1"/><joint type="hinge" axis="0 -1 0"/>'
                     f'<geom {box(b)} mass="{b.mass!r}" {mu}/></body>')
    parts.append("</worldbody>")
    if scene.amplitude:
        parts.append('<contact><exclude body1="world" body2="base"/></contact>')
    parts.append("</mujoco>")
    return "".join(parts)


def mujoco_run(scene):
    import mujoco

    model = mujoco.MjModel.from_xml_string(mujoco_xml(scene))
    data = mujoco.MjData(model)
    shaken = 1 if scene.amplitude else 0
    data.qpos[shaken:] = initial_state(scene).ravel()
    times, states = [0.0], [mujoco_pose(data, shaken)]
    spent = 0.0
    for _ in range(scene.steps):
        start = time.perf_counter()
        if shaken:
            data.qpos[0], data.qvel[0] = scene.base_x(data.time), scene.base_v(data.time)
        mujoco.mj_step(model, data)
        spent += time.perf_counter() - start
        times.append(data.time)
        states.append(mujoco_pose(data, shaken))
    return spent / scene.steps, np.array(times), np.array(states)


def mujoco_pose(data, shaken):
    base = [data.qpos[0] if shaken else 0.0, 0.0, 0.0]
    return np.vstack([base, data.qpos[shaken:].reshape(-1, 3)])


def mujoco_settings():
    import mujoco

    # A model with one geom, for the defaults of the options and of a geom's contact.
    model = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><geom size='1'/></worldbody></mujoco>")
    opt = model.opt
    enum = lambda e, v: e(v).name.split("_", 1)[1].lower()  # noqa: E731
    return {
        "version": mujoco.__version__,
        "integrator": enum(mujoco.mjtIntegrator, opt.integrator),
        "cone": enum(mujoco.mjtCone, opt.cone),
        "solver": enum(mujoco.mjtSolver, opt.solver),
        "iterations": int(opt.iterations),
        "tolerance": float(opt.tolerance),
        "impratio": float(opt.impratio),
        "noslip_iterations": int(opt.noslip_iterations),
        "condim": int(model.geom_condim[0]),
        "solref": model.geom_solref[0].tolist(),
        "solimp": model.geom_solimp[0].tolist(),
        "margin": float(model.geom_margin[0]),
        "friction": "mu of the scene (sliding), the default torsional 0.005 and rolling 0.0001",
    }


def import_pybullet():
    """pybullet, imported without the banner its C code prints on stdout (which would
    break --json)."""
    import ctypes

    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 1)
            import pybullet

            ctypes.CDLL(None).fflush(None)
    finally:
        os.dup2(saved, 1)
        os.close(saved)
    return pybullet


def pybullet_world(scene):
    """A PyBullet client with the scene: (client, base id or None, block ids)."""
    p = import_pybullet()

    client = p.connect(p.DIRECT)
    p.setGravity(0, 0, -scene.gravity, physicsClientId=client)
    p.setPhysicsEngineParameter(fixedTimeStep=scene.dt, physicsClientId=client)
    depth = min(b.width for b in scene.blocks)
    shape = lambda b: p.createCollisionShape(  # noqa: E731
        p.GEOM_BOX, halfExtents=[b.width / 2, depth / 2, b.height / 2], physicsClientId=client)
    floor = p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client),
                              basePosition=[0, 0, scene.floor], physicsClientId=client)
    bodies = [(floor, -1)]
    base = None
    if scene.amplitude:
        mass = BASE_MASS_RATIO * sum(b.mass for b in scene.blocks)
        base = jointed(p, client, [mass], [shape(scene.base)], [p.JOINT_PRISMATIC], [[1, 0, 0]])
        p.setCollisionFilterPair(floor, base, -1, 0, 0, physicsClientId=client)
        bodies.append((base, 0))
    else:
        bodies.append((p.createMultiBody(0, shape(scene.base), physicsClientId=client), -1))
    blocks = []
    for b in scene.blocks:
        # Slide x, slide z, hinge about −y; the two sliding links are massless in effect.
        body = jointed(p, client, [1e-9, 1e-9, b.mass], [-1, -1, shape(b)],
                       [p.JOINT_PRISMATIC, p.JOINT_PRISMATIC, p.JOINT_REVOLUTE],
                       [[1, 0, 0], [0, 0, 1], [0, -1, 0]])
        for j, q in enumerate((b.x, b.y, b.theta)):
            p.resetJointState(body, j, q, 0.0, physicsClientId=client)
        blocks.append(body)
        bodies.append((body, 2))
    for body, link in bodies:
        p.changeDynamics(body, link, lateralFriction=scene.mu, restitution=0.0,
                         physicsClientId=client)
    return client, base, blocks


def jointed(p, client, masses, shapes, types, axes):
    """A body on a chain of joints from a fixed root at the origin, its motors off and
    no damping."""
    n = len(masses)
    body = p.createMultiBody(
        baseMass=0, baseCollisionShapeIndex=-1, linkMasses=masses,
        linkCollisionShapeIndices=shapes, linkVisualShapeIndices=[-1] * n,
        linkPositions=[[0, 0, 0]] * n, linkOrientations=[[0, 0, 0, 1]] * n,
        linkInertialFramePositions=[[0, 0, 0]] * n,
        linkInertialFrameOrientations=[[0, 0, 0, 1]] * n,
        linkParentIndices=list(range(n)), linkJointTypes=types, linkJointAxis=axes,
        physicsClientId=client)
    p.setJointMotorControlArray(body, list(range(n)), p.VELOCITY_CONTROL, forces=[0] * n,
                                physicsClientId=client)
    for link in range(-1, n):
        p.changeDynamics(body, link, linearDamping=0, angularDamping=0, jointDamping=0,
                         physicsClientId=client)
    return body


def pybullet_run(scene):
    p = import_pybullet()

    client, base, blocks = pybullet_world(scene)
    t, spent = 0.0, 0.0
    times, states = [0.0], [pybullet_pose(p, client, scene, base, blocks)]
    try:
        for k in range(scene.steps):
            start = time.perf_counter()
            if base is not None:
                p.resetJointState(base, 0, scene.base_x(t), scene.base_v(t), physicsClientId=client)
            p.stepSimulation(physicsClientId=client)
            spent += time.perf_counter() - start
            t = (k + 1) * scene.dt
            times.append(t)
            states.append(pybullet_pose(p, client, scene, base, blocks))
    finally:
        p.disconnect(physicsClientId=client)
    return spent / scene.steps, np.array(times), np.array(states)


def pybullet_pose(p, client, scene, base, blocks):
    x = p.getJointState(base, 0, physicsClientId=client)[0] if base is not None else 0.0
    rows = [[x, 0.0, 0.0]]
    for body in blocks:
        rows.append([s[0] for s in p.getJointStates(body, [0, 1, 2], physicsClientId=client)])
    return np.array(rows)


def pybullet_settings():
    import importlib.metadata

    p = import_pybullet()
    client = p.connect(p.DIRECT)
    params = p.getPhysicsEngineParameters(physicsClientId=client)
    p.disconnect(physicsClientId=client)
    keep = ("numSolverIterations", "numSubSteps", "numNonContactInnerIterations")
    settings = {k: v for k, v in params.items() if k in keep}
    settings["version"] = importlib.metadata.version("pybullet")
    settings["contact"] = ("the defaults (Bullet's multibody solver, ERP, margins, slop); "
                           "lateralFriction mu, restitution 0")
    return settings


PEERS = {"mujoco": (mujoco_run, mujoco_settings), "pybullet": (pybullet_run, pybullet_settings)}


def available_peers(names, notes):
    """The peers of `names` that import, each with its settings; notes the others."""
    peers = {}
    for name in names:
        run, settings = PEERS[name]
        try:
            peers[name] = (run, settings())
        except ImportError as err:
            notes.append(f"{name}: not installed ({err}); left out (pip install {name})")
    return peers


# ---------------------------------------------------------------------------------------
# The benchmark.


def reference(binary, scene, notes):
    """rollstack's reference run of a scene: it fills in the scene's μ, g, Δt and steps
    from rollstack's JSON, checks the scene's geometry against rollstack's t = 0 state,
    and measures rollstack's run with the same code as the peers'."""
    with tempfile.TemporaryDirectory() as tmp:
        report = rollstack_run(binary, scene, os.path.join(tmp, "out"))
        s = report["scene"]
        scene.mu, scene.gravity, scene.dt, scene.steps = s["mu"], s["gravity"], s["dt"], s["steps"]
        scene.settings = {k: s[k] for k in ("rho_inf", "tol", "prox")}
        times, states = rollstack_states(scene, os.path.join(tmp, "out", "trajectory.csv"))
    built = np.vstack([[scene.base_x(0.0), 0.0, 0.0], initial_state(scene)])
    gap = np.abs(states[0] - built).max()
    if gap > 1e-12 or s["floor"] != scene.floor or s["blocks"] != len(scene.blocks):
        raise RuntimeError(f"{scene.name}: the script's scene is not rollstack's "
                           f"(t = 0 differs by {gap:g})")
    base_gap = max(abs(x - scene.base_x(t)) for t, x in zip(times, states[:, 0, 0]))
    if base_gap > 1e-12:
        raise RuntimeError(f"{scene.name}: the base motion is not rollstack's (by {base_gap:g})")
    ours = measures(scene, times, states)
    check(scene, ours, report, notes)
    return ours


def check(scene, ours, report, notes):
    """This script's measures of rollstack's trajectory against rollstack's own JSON."""
    theirs = outcome(report["events"])
    if theirs != ours["outcome"]:
        notes.append(f"{scene.name}: this script reads rollstack's outcome as "
                     f"{ours['outcome']}, rollstack says {theirs}")
    if abs(ours["max_penetration"] - report["max_penetration"]) > 1e-9:
        notes.append(f"{scene.name}: this script reads rollstack's penetration as "
                     f"{ours['max_penetration']:.3g}, "
                     f"rollstack says {report['max_penetration']:.3g}")


def benchmark(binary, scenes_, peers, repeat, notes, log):
    results = {s.name: {} for s in scenes_}
    per_step = {s.name: {} for s in scenes_}
    for s in scenes_:
        log(f"{s.name}: rollstack reference run")
        results[s.name]["rollstack"] = reference(binary, s, notes)
    for r in range(repeat):
        for s in scenes_:
            for engine in ["rollstack"] + list(peers):
                log(f"repeat {r + 1}/{repeat}: {s.name}, {engine}")
                try:
                    if engine == "rollstack":
                        report = rollstack_run(binary, s)
                        seconds = report["wall_time_s"] / report["steps"]
                    else:
                        seconds, times, states = peers[engine][0](s)
                        if r == 0:
                            results[s.name][engine] = measures(s, times, states)
                except Exception as err:  # an engine's failure is a result, not the end
                    results[s.name][engine] = {"error": str(err)}
                    continue
                per_step[s.name].setdefault(engine, []).append(seconds * 1e6)
    for s in scenes_:
        for engine, runs in per_step[s.name].items():
            results[s.name][engine]["us_per_step"] = statistics.median(runs)
            results[s.name][engine]["us_per_step_runs"] = runs
    return results


# ---------------------------------------------------------------------------------------
# Output.


def outcome_text(result):
    """The failure, the blocks that fell in that order, those on the floor."""
    if "error" in result:
        return f"error: {result['error']}"
    o = result["outcome"]
    if o["failure"] is None:
        return "standing"
    f = o["failure"]
    who = f"block {f['block']} " if f["block"] else ""
    text = f"failed t = {f['t']:.2f} ({who}{f['kind'].replace('_', ' ')})"
    if o["fell"]:
        text += f"; fell {listing(o['fell'])}"
    if o["on_floor"]:
        text += f"; on the floor {listing(o['on_floor'])}"
    return text


def listing(blocks, most=10):
    """Block numbers, the first `most` of a longer list and how many in all."""
    shown = ", ".join(str(k) for k in blocks[:most])
    return shown if len(blocks) <= most else f"{shown}, … ({len(blocks)} in all)"


def rows(scenes_, results):
    out = []
    for s in scenes_:
        ours = results[s.name]["rollstack"].get("us_per_step")
        for engine, r in results[s.name].items():
            us = r.get("us_per_step")
            runs = r.get("us_per_step_runs", [])
            spread = f"{min(runs):.1f}–{max(runs):.1f}" if runs else ""
            ratio = f"{us / ours:.2f}" if us and ours else ""
            pen = f"{r['max_penetration']:.2e}" if "max_penetration" in r else ""
            out.append([s.name, engine, f"{us:.1f}" if us else "", spread, ratio, pen,
                        outcome_text(r)])
    return out


HEADER = ["scene", "engine", "µs/step", "range", "÷ rollstack", "max penetration", "outcome"]


def text_table(table):
    widths = [max(len(r[i]) for r in [HEADER] + table) for i in range(len(HEADER))]
    line = lambda r: "  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip()  # noqa: E731
    return "\n".join([line(HEADER)] + [line(r) for r in table])


def markdown_table(table):
    lines = ["| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    lines += ["| " + " | ".join(r) + " |" for r in table]
    return "\n".join(lines)


def describe(scenes_, settings, repeat):
    lines = [f"repeats: {repeat} (median µs per step); {os.cpu_count()} CPUs, "
             f"{platform.platform()}"]
    for s in scenes_:
        lines.append(f"{s.name}: {s.label}; dt = {s.dt:.6g}, {s.steps} steps, g = {s.gravity:g}, "
                     f"mu = {s.mu:g}: rollstack {' '.join(s.args)}")
    for engine, values in settings.items():
        lines.append(f"{engine}: " + ", ".join(f"{k} = {v}" for k, v in values.items()))
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("binary", nargs="?", default="target/release/rollstack",
                    help="the rollstack binary (default target/release/rollstack)")
    ap.add_argument("--repeat", type=int, default=3,
                    help="timed runs per scene and engine, their median reported (default 3)")
    ap.add_argument("--scenes",
                    help="comma-separated: column10, shaken6, lire10, column100 (default all)")
    ap.add_argument("--engines", default="mujoco,pybullet",
                    help="the peers, comma-separated (default mujoco,pybullet)")
    output = ap.add_mutually_exclusive_group()
    output.add_argument("--json", action="store_true", help="print one JSON object")
    output.add_argument("--markdown", action="store_true", help="print the table as markdown")
    ap.add_argument("--smoke", action="store_true", help="one scene, 5 steps, one repeat")
    args = ap.parse_args()
    if args.repeat < 1:
        ap.error(f"--repeat {args.repeat}: at least 1")
    if not os.access(args.binary, os.X_OK):
        ap.error(f"{args.binary}: no rollstack binary there "
                 "(cargo build --release -p rollstack, or give its path)")
    chosen = scenes(args.smoke)
    if args.scenes:
        names = args.scenes.split(",")
        unknown = [n for n in names if n not in {s.name for s in chosen}]
        if unknown:
            known = ", ".join(s.name for s in chosen)
            ap.error(f"--scenes {args.scenes}: unknown {', '.join(unknown)} (known: {known})")
        chosen = [s for s in chosen if s.name in names]
    engines = [e for e in args.engines.split(",") if e]
    if any(e not in PEERS for e in engines):
        ap.error(f"--engines {args.engines}: the peers are {', '.join(PEERS)}")
    repeat = 1 if args.smoke else args.repeat
    notes = []
    peers = available_peers(engines, notes)
    log = lambda m: print(m, file=sys.stderr, flush=True)  # noqa: E731
    try:
        results = benchmark(args.binary, chosen, peers, repeat, notes, log)
    except RuntimeError as err:
        sys.exit(f"error: {err}")
    settings = {"rollstack": {"binary": args.binary, **chosen[0].settings}}
    settings.update({name: values for name, (_, values) in peers.items()})
    if args.json:
        print(json.dumps({
            "repeat": repeat, "cpus": os.cpu_count(), "platform": platform.platform(),
            "engines": settings, "notes": notes,
            "scenes": [{"name": s.name, "label": s.label, "rollstack_args": s.args, "dt": s.dt,
                        "steps": s.steps, "mu": s.mu, "gravity": s.gravity,
                        "results": results[s.name]} for s in chosen],
        }))
        return
    table = rows(chosen, results)
    print(markdown_table(table) if args.markdown else text_table(table))
    print()
    for line in describe(chosen, settings, repeat) + [f"note: {n}" for n in notes]:
        print(f"- {line}" if args.markdown else line)


if __name__ == "__main__":
    main()
