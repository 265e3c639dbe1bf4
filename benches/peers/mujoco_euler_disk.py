"""One full Euler's-disk run (scenarios/euler-disk.toml) in MuJoCo and in our tool: the
time each takes and whether the disc reaches the landing.

MuJoCo's body is a `cylinder` geom (radius 37.5 mm, half-height 6.5 mm: sharp edges where
ours has 1.6 mm fillets) with a free joint on a `plane`, the scenario's mass and inertia,
started in the scenario's state: tilt 20 degrees, the Euler rates phi_dot and psi_dot
(z-x-z, as scene.py), the lowest point of the lower edge on the plane and
v_G = -omega x (r_contact - r_G) (rolling, no slip). MuJoCo has neither of our dissipation
laws (rolling friction mu_r = 1e-4, a force mu_r N against the contact point's travel; an
air boundary layer), so three setups are run:

- `rolling`: condim 6, sliding friction 1 (no slip: our rolling model grips), torsional 0,
  rolling friction mu_roll = 3 mu_r R / theta0 = 3.2e-5 m. MuJoCo's rolling friction is a
  couple mu_roll N against the rolling angular velocity (our `rolling_resistance`); this
  coefficient gives the same closed-form landing time of a thin disc as our mu_r
  (docs/physics.md, "Dissipation of a rolling disc": t0 = (3/2) R^{3/2} theta0^{1/2} /
  (mu_roll g^{1/2}) against theta0^{3/2} / (2 mu_r (g/R)^{1/2})).
- `no law`: condim 3, sliding friction 1, no rolling friction: every change of the
  energy is MuJoCo's own (its soft contact and its integrator).
- `rolling, default contact`: as `rolling` with MuJoCo's default solref (0.02 s, 1), what
  a model gets out of the box. The other two use solref = (2 dt, 1), the stiffest contact
  MuJoCo accepts at that step.

Each runs 70 simulated seconds (or until it becomes non-finite or MuJoCo resets it), with
RK4 and implicitfast at dt = 1e-3 and 1e-4 s, and `rolling` with implicitfast at 1e-5 s.
Reported: the wall time of mj_step over the whole run (chunks of 10 ms of simulated time;
median of 3 runs when it has at most 1e5 steps, else one run), then from a second, sampled
run (the state every 1 ms): when the tilt (the axis's angle from the vertical) first falls
below 1e-3 and 1e-5 rad, the tilt and the precession rate at 60 s, whether it ends lying
flat at rest (tilt < 1e-3 rad, |v_G| < 1 mm/s, |omega| < 0.01 rad/s), the deepest point of
the body below the floor, the share of samples without a contact (the disc hopping), and
the energy (MuJoCo's mj_energyPos + mj_energyVel) as a fraction of what there is to lose,
E0 - m g h: its largest rise and what is left at the end. Ours: the whole `ellipsoid run` process over the same 70 s (median of 3; samples every
1 ms to CSV), the `flat` event's time, the same tilts and rates from its CSV, the final
mode and the E + W drift. About 3 minutes on 2 cores.

    /work/devvenv/bin/python benches/peers/mujoco_euler_disk.py --bin target/release/ellipsoid --markdown
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import subprocess
import sys
import tempfile
import time
import tomllib
import types
from pathlib import Path

import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scene as sc  # noqa: E402

SCENARIO = sc.ROOT / "scenarios" / "euler-disk.toml"
T_END = 70.0
SAMPLE = 1e-3  # simulated seconds between samples in the observed run
CHUNK = 0.01  # simulated seconds per mj_step call in the timed run
RADIUS = 0.0375  # the disc's outer radius and half-thickness (the cylinder geom)
HALF_HEIGHT = 0.0065
SLIDING = 1.0
CONFIGS = [
    ("rolling", "RK4", 1e-3), ("rolling", "RK4", 1e-4),
    ("rolling", "implicitfast", 1e-3), ("rolling", "implicitfast", 1e-4),
    ("no law", "RK4", 1e-3), ("no law", "RK4", 1e-4),
    ("no law", "implicitfast", 1e-3), ("no law", "implicitfast", 1e-4),
    ("rolling, default contact", "RK4", 1e-3), ("rolling, default contact", "RK4", 1e-4),
    ("rolling", "implicitfast", 1e-5),  # 7e6 steps: where the stiffer contact leads
]  # fmt: skip
FLAT, FLATTER = 1e-3, 1e-5  # tilts reported [rad]


def load_disc() -> dict:
    doc = tomllib.loads(SCENARIO.read_text())
    body, init, eff = doc["body"], doc["initial"], doc["effects"]
    inertia = [float(v) for v in body["inertia"]]
    theta = sc._angle(init, "theta")
    return {
        "mass": float(body["mass"]),
        "inertia": inertia,
        "theta": theta,
        "phi_dot": sc._angle(init, "phi_dot"),
        "psi_dot": sc._angle(init, "psi_dot"),
        "gravity": float(eff.get("gravity", 9.81)),
        "mu_r": float(eff["rolling_friction"]),
        "mu_roll": 3.0 * float(eff["rolling_friction"]) * RADIUS / theta,
    }


def mjcf(disc: dict, setup: str, integrator: str, dt: float) -> str:
    if setup == "no law":
        condim, friction = 3, f"{SLIDING} 0 0"
    else:
        condim, friction = 6, f"{SLIDING} 0 {disc['mu_roll']}"
    solref = "0.02 1" if setup.endswith("default contact") else f"{2 * dt} 1"
    i = disc["inertia"]
    geom = f'condim="{condim}" friction="{friction}" solref="{solref}"'
    return f"""
<mujoco model="euler-disk">
  <option timestep="{dt}" integrator="{integrator}" gravity="0 0 {-disc['gravity']}">
    <flag energy="enable"/>
  </option>
  <worldbody>
    <geom name="floor" type="plane" size="0 0 1" {geom}/>
    <body name="disc">
      <freejoint/>
      <inertial pos="0 0 0" mass="{disc['mass']}" diaginertia="{i[0]} {i[1]} {i[2]}"/>
      <geom type="cylinder" size="{RADIUS} {HALF_HEIGHT}" {geom}/>
    </body>
  </worldbody>
</mujoco>"""


def initial(disc: dict, m: mujoco.MjModel, d: mujoco.MjData) -> None:
    """The scenario's attitude and rates; the lowest point of the lower edge on the
    plane, G moving so that the material point there is at rest."""
    rates = types.SimpleNamespace(theta=disc["theta"], psi=0.0, theta_dot=0.0,
                                  phi_dot=disc["phi_dot"], psi_dot=disc["psi_dot"])  # fmt: skip
    w_body = sc.omega_body(rates)
    r = sc.euler_rotation(disc["theta"], 0.0, 0.0)
    zeta = r[2, :]  # world up in body axes
    across = np.array([zeta[0], zeta[1], 0.0])
    contact_body = np.array([0.0, 0.0, -HALF_HEIGHT]) - RADIUS * across / np.linalg.norm(across)
    contact = r @ contact_body  # from G, world axes
    d.qpos[:3] = [0.0, 0.0, -contact[2]]
    d.qpos[3:7] = sc.quat_from_rotation(r)
    d.qvel[:3] = -np.cross(r @ w_body, contact)
    d.qvel[3:6] = w_body  # body axes (free joint)
    mujoco.mj_forward(m, d)


def bad(d: mujoco.MjData, t_expected: float) -> bool:
    """Non-finite, or MuJoCo reset the state after a bad acceleration."""
    warned = d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0
    return warned or not np.all(np.isfinite(d.qpos)) or abs(d.time - t_expected) > 1e-3


def timed(disc: dict, setup: str, integrator: str, dt: float) -> tuple[float, int, int, bool]:
    """(wall time of the whole run, steps, runs timed, blew up)."""
    m = mujoco.MjModel.from_xml_string(mjcf(disc, setup, integrator, dt))
    d = mujoco.MjData(m)
    n = round(T_END / dt)
    chunk = max(1, round(CHUNK / dt))
    repeats = 3 if n <= 100_000 else 1
    walls, blew = [], False
    for _ in range(repeats):
        mujoco.mj_resetData(m, d)
        initial(disc, m, d)
        done = 0
        t0 = time.perf_counter()
        while done < n:
            k = min(chunk, n - done)
            mujoco.mj_step(m, d, nstep=k)
            done += k
            if bad(d, done * dt):
                blew = True
                break
        walls.append(time.perf_counter() - t0)
        if blew:
            break
    return float(np.median(walls)), done, len(walls), blew


def observed(disc: dict, setup: str, integrator: str, dt: float) -> dict:
    """The run sampled every 1 ms: tilt, precession rate, energy, depth, rest."""
    m = mujoco.MjModel.from_xml_string(mjcf(disc, setup, integrator, dt))
    d = mujoco.MjData(m)
    initial(disc, m, d)
    k = max(1, round(SAMPLE / dt))
    n_samples = round(T_END / (k * dt))
    t = np.full(n_samples + 1, np.nan)
    tilt, energy, depth, prec, ncon = (np.full(n_samples + 1, np.nan) for _ in range(5))
    bid = m.body("disc").id
    mass, g = disc["mass"], disc["gravity"]
    blew = False
    for j in range(n_samples + 1):
        if j:
            mujoco.mj_step(m, d, nstep=k)
            if bad(d, j * k * dt):
                blew = True
                break
        mujoco.mj_kinematics(m, d)  # xmat, xipos of this state (mj_step leaves the step's start)
        mujoco.mj_energyPos(m, d)
        mujoco.mj_energyVel(m, d)  # M is constant for this body: G at the frame origin
        r = d.xmat[bid].reshape(3, 3)
        axis = r[:, 2]
        horiz = math.hypot(axis[0], axis[1])
        t[j] = d.time
        ncon[j] = d.ncon  # found at the start of the last step
        tilt[j] = math.atan2(horiz, abs(axis[2]))
        energy[j] = d.energy[0] + d.energy[1]
        depth[j] = -(d.xpos[bid][2] - HALF_HEIGHT * abs(axis[2]) - RADIUS * horiz)
        # precession rate phi_dot of z-x-z angles: w.e3 = phi_dot + psi_dot cos(theta),
        # w.n = phi_dot cos(theta) + psi_dot
        w = r @ d.qvel[3:6]
        if horiz > 1e-9:
            n_up = axis if axis[2] >= 0 else -axis
            prec[j] = (w[2] - n_up[2] * (w @ n_up)) / horiz**2
    ok = np.isfinite(t)
    t, tilt, energy, depth, prec, ncon = t[ok], tilt[ok], energy[ok], depth[ok], prec[ok], ncon[ok]
    available = energy[0] - mass * g * HALF_HEIGHT
    rise = float(np.max(energy - np.minimum.accumulate(energy)))
    v = float(np.linalg.norm(d.qvel[:3]))
    w = float(np.linalg.norm(d.qvel[3:6]))
    at60 = np.searchsorted(t, 60.0 - 1e-9)
    return {
        "t_end": float(t[-1]),
        "blew": blew,
        "flat": first_below(t, tilt, FLAT),
        "flatter": first_below(t, tilt, FLATTER),
        "tilt60": float(tilt[at60]) if at60 < len(t) else math.nan,
        "prec60": float(prec[at60]) if at60 < len(t) else math.nan,
        "rest": bool(not blew and tilt[-1] < FLAT and v < 1e-3 and w < 1e-2),
        "tilt_end": float(tilt[-1]),
        "depth": float(np.max(depth)),
        "no_contact": float(np.mean(ncon == 0)),  # hops: the contact chatters
        "rise": rise / available,
        "left": float((energy[-1] - mass * g * HALF_HEIGHT) / available),
    }


def first_below(t: np.ndarray, x: np.ndarray, level: float) -> float:
    idx = np.nonzero(x < level)[0]
    return float(t[idx[0]]) if len(idx) else math.nan


def ours(binary: Path, work: Path) -> dict:
    """Our whole `ellipsoid run` process (median of 3) and its outcome."""
    out, summary = work / "ours.csv", work / "ours.json"
    args = [str(binary), "run", str(SCENARIO), "-o", str(out), "--summary", str(summary), "-q",
            "--set", f"output.t_end={T_END}"]  # fmt: skip
    walls = []
    for _ in range(3):
        t0 = time.perf_counter()
        subprocess.run(args, check=True)
        walls.append(time.perf_counter() - t0)
    s = json.loads(summary.read_text())
    with open(out) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    t = np.array([float(r["t"]) for r in rows])
    tilt = np.abs(np.array([float(r["theta"]) for r in rows]))
    energy = np.array([float(r["energy"]) for r in rows])
    at60 = np.searchsorted(t, 60.0 - 1e-9)
    disc = load_disc()
    solver = tomllib.loads(SCENARIO.read_text()).get("solver", {})
    e_flat = disc["mass"] * disc["gravity"] * s["final"]["z"]
    flat_events = [float(e["t"]) for e in s.get("events", []) if e.get("kind") == "flat"]
    return {
        "wall": float(np.median(walls)),
        "method": f"{solver.get('method', 'dop853').upper()}, rtol = {solver.get('rtol', 1e-10):g}",
        "status": s["status"],
        "steps": int(s["stats"]["accepted"]),
        "flat_event": flat_events[0] if flat_events else math.nan,
        "flat": first_below(t, tilt, FLAT),
        "flatter": first_below(t, tilt, FLATTER),
        "tilt60": float(tilt[at60]),
        "prec60": float(rows[at60]["phi_dot"]),
        "mode": s["final"]["mode"],
        "rest": bool(
            s["final"]["mode"].startswith("face")
            and math.hypot(s["final"]["vx"], s["final"]["vy"]) < 1e-3
            and math.sqrt(sum(s["final"][f"omega_{a}"] ** 2 for a in "xyz")) < 1e-2
        ),
        "t_end": float(s["final"]["t"]),
        "drift": float(s["drift"]["energy_plus_work"]),
        "rise": float(np.max(energy - np.minimum.accumulate(energy)) / (energy[0] - e_flat)),
        "left": float((energy[-1] - e_flat) / (energy[0] - e_flat)),
    }


def fmt_t(x: float) -> str:
    return "never" if math.isnan(x) else f"{x:.2f} s"


def fmt_len(x: float) -> str:
    for unit, scale in (("mm", 1e-3), ("µm", 1e-6), ("nm", 1e-9)):
        if abs(x) >= scale:
            return f"{x / scale:.3g} {unit}"
    return f"{x * 1e9:.2g} nm"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", type=Path, default=sc.DEFAULT_BIN)
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args()
    disc = load_disc()
    print(f"MuJoCo {mujoco.__version__}; mu_roll = {disc['mu_roll']:.3e} m", file=sys.stderr)
    rows = []
    for setup, integ, dt in CONFIGS:
        wall, steps, runs, blew_t = timed(disc, setup, integ, dt)
        o = observed(disc, setup, integ, dt)
        o.update(setup=setup, integ=integ, dt=dt, wall=wall, steps=steps, runs=runs, blew=o["blew"] or blew_t)
        rows.append(o)
        print(f"{setup:<25} {integ:<12} dt {dt:.0e}: {wall:7.2f} s ({runs} run(s), {steps} steps), "
              f"tilt < 1e-3 at {fmt_t(o['flat'])}, < 1e-5 at {fmt_t(o['flatter'])}, "
              f"tilt(60 s) {o['tilt60']:.3g} rad, precession(60 s) {o['prec60']:.4g} rad/s, "
              f"at rest flat {o['rest']} (tilt {o['tilt_end']:.2g} rad), depth {fmt_len(o['depth'])}, no contact in {o['no_contact']:.1%} of samples, "
              f"energy rise {o['rise']:.1%}, left {o['left']:.1%}, blew up {o['blew']}", file=sys.stderr)  # fmt: skip
    with tempfile.TemporaryDirectory() as tmp:
        us = ours(args.bin, Path(tmp))
    print(f"ours: {us}", file=sys.stderr)
    if args.markdown:
        print("| run | method | dt | steps | wall time | tilt < 1e-3 rad | tilt < 1e-5 rad | tilt, precession rate at 60 s | lying flat at rest at 70 s | deepest point below the floor | samples without contact | largest energy rise | energy left at 70 s |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        print(f"| ours | {us['method']} | adaptive | {us['steps']:,} | {us['wall']:.2f} s (median of 3) | {fmt_t(us['flat'])} | "
              f"{fmt_t(us['flatter'])} (`flat` at {fmt_t(us['flat_event'])}) | {us['tilt60']:.3f} rad, {us['prec60']:.0f} rad/s | "
              f"{'yes' if us['rest'] else 'no'} (mode `{us['mode']}`) | 0 (exact contact) | 0 | {us['rise']:.1%} | "
              f"{us['left']:.1%} (E + W drift {us['drift']:.0e}) |")  # fmt: skip
        for o in rows:
            note = f", blew up at {o['t_end']:.2f} s" if o["blew"] else ""
            runs = "median of 3" if o["runs"] == 3 else "1 run"
            print(f"| MuJoCo, {o['setup']} | {o['integ']} | {o['dt']:.0e} s | {o['steps']:,} | {o['wall']:.2f} s ({runs}{note}) | "
                  f"{fmt_t(o['flat'])} | {fmt_t(o['flatter'])} | {o['tilt60']:.3f} rad, {o['prec60']:.0f} rad/s | "
                  f"{'yes' if o['rest'] else 'no'} (tilt {o['tilt_end']:.1e} rad) | {fmt_len(o['depth'])} | {o['no_contact']:.1%} | {o['rise']:.1%} | {o['left']:.1%} |")  # fmt: skip
    else:
        print(us)
        for o in rows:
            print(o)


if __name__ == "__main__":
    main()
