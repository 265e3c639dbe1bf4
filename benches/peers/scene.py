"""Shared by the peer scripts: read one of our TOML scenarios (the keys the peer scenes
use), build its initial state, and the physics of docs/physics.md in plain numpy.

State layout (as crates/ellipsoid-core/src/state.rs):
    0..2 x_G, y_G | 2..6 quaternion (w, x, y, z), body -> world | 6..8 v_Gx, v_Gy
    8..11 omega (body axes) | 11 W (dissipated work) | 12..14 unused here
SI units throughout.
"""
from __future__ import annotations

import math
import subprocess
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_BIN = ROOT / "target" / "release" / "ellipsoid"


@dataclass
class Scene:
    name: str
    a: float
    b: float
    c: float
    mass: float
    g_b: np.ndarray  # G - C0 in body axes (m)
    inertia: np.ndarray  # 3x3 about G, body axes (kg m^2)
    gravity: float
    model: str  # "frictionless" | "sliding"
    friction: float
    theta: float
    phi: float
    psi: float
    theta_dot: float
    phi_dot: float
    psi_dot: float
    position: np.ndarray
    velocity: np.ndarray
    t_end: float
    rtol: float
    atol: float

    @property
    def A2(self) -> np.ndarray:
        return np.diag([self.a**2, self.b**2, self.c**2])

    @property
    def i_inv(self) -> np.ndarray:
        return np.linalg.inv(self.inertia)


def _angle(table: dict, key: str, default: float = 0.0) -> float:
    if key in table:
        return float(table[key])
    if key + "_deg" in table:
        return math.radians(float(table[key + "_deg"]))
    return default


def load(path: Path) -> Scene:
    """The subset of the scenario format the peer scenes use (no effects, no rotation list)."""
    doc = tomllib.loads(Path(path).read_text())
    body, init, contact = doc["body"], doc.get("initial", {}), doc["contact"]
    for unsupported in ("rotation", "omega_body", "omega_body_deg", "com_offset_vector"):
        if unsupported in init or unsupported in body:
            raise SystemExit(f"{path}: {unsupported} is not supported by the peer scripts")
    if doc.get("effects", {}).keys() - {"gravity"}:
        raise SystemExit(f"{path}: effects are not supported by the peer scripts")
    if contact["model"] not in ("frictionless", "sliding"):
        raise SystemExit(f"{path}: the peer scripts implement the frictionless and sliding models only")
    a = float(body["a"])
    inertia = body["inertia"]
    if isinstance(inertia, list) and not isinstance(inertia[0], list):
        inertia = np.diag([float(v) for v in inertia])
    else:
        inertia = np.array(inertia, dtype=float)
    solver = doc.get("solver", {})
    return Scene(
        name=Path(path).stem,
        a=a,
        b=float(body.get("b", a)),
        c=float(body["c"]),
        mass=float(body["mass"]),
        g_b=np.array([0.0, 0.0, -float(body.get("com_offset", 0.0))]),
        inertia=inertia,
        gravity=float(doc.get("effects", {}).get("gravity", 9.81)),
        model=contact["model"],
        friction=float(contact.get("friction", 0.0)),
        theta=_angle(init, "theta"),
        phi=_angle(init, "phi"),
        psi=_angle(init, "psi"),
        theta_dot=_angle(init, "theta_dot"),
        phi_dot=_angle(init, "phi_dot"),
        psi_dot=_angle(init, "psi_dot"),
        position=np.array(init.get("position", [0.0, 0.0]), dtype=float),
        velocity=np.array(init.get("velocity", [0.0, 0.0]), dtype=float),
        t_end=float(doc["output"]["t_end"]),
        rtol=float(solver.get("rtol", 1e-10)),
        atol=float(solver.get("atol", 1e-12)),
    )


def rot_z(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_x(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def euler_rotation(theta: float, phi: float, psi: float) -> np.ndarray:
    """R = Rz(phi) Rx(theta) Rz(psi) (paper eq. 1, z-x-z)."""
    return rot_z(phi) @ rot_x(theta) @ rot_z(psi)


def quat_from_rotation(r: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method)."""
    tr = np.trace(r)
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2]) * 2
        q = [(r[2, 1] - r[1, 2]) / s, 0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
    elif r[1, 1] > r[2, 2]:
        s = math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2]) * 2
        q = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s]
    else:
        s = math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1]) * 2
        q = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    return q / np.linalg.norm(q)


def rotation(q: np.ndarray) -> np.ndarray:
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def omega_body(s: Scene) -> np.ndarray:
    st, ct, sp, cp = math.sin(s.theta), math.cos(s.theta), math.sin(s.psi), math.cos(s.psi)
    return np.array(
        [
            s.phi_dot * st * sp + s.theta_dot * cp,
            s.phi_dot * st * cp - s.theta_dot * sp,
            s.phi_dot * ct + s.psi_dot,
        ]
    )


def initial_state(s: Scene) -> np.ndarray:
    y = np.zeros(14)
    y[0:2] = s.position
    y[2:6] = quat_from_rotation(euler_rotation(s.theta, s.phi, s.psi))
    y[6:8] = s.velocity
    y[8:11] = omega_body(s)
    return y


def contact(s: Scene, r: np.ndarray):
    """zeta (world up in body axes), r_b = C - G, height of G, Hessian H (docs/physics.md)."""
    zeta = r[2, :]
    a2z = s.A2 @ zeta
    sq = math.sqrt(zeta @ a2z)
    p_c = -a2z / sq
    r_b = p_c - s.g_b
    height = sq + zeta @ s.g_b
    hess = s.A2 / sq - np.outer(a2z, a2z) / sq**3
    return zeta, r_b, height, hess


def kinematics(s: Scene, y: np.ndarray):
    """Rotation, omega, contact quantities, full v_G (v_Gz from the constraint)."""
    r = rotation(y[2:6])
    w = y[8:11]
    zeta, r_b, height, hess = contact(s, r)
    w_world = r @ w
    r_world = r @ r_b
    wxr = np.cross(w_world, r_world)
    v_g = np.array([y[6], y[7], -wxr[2]])
    return r, w, zeta, r_b, height, hess, v_g, wxr


def rhs(s: Scene, y: np.ndarray) -> np.ndarray:
    """dy/dt for the frictionless or sliding model (docs/physics.md models 1, 2)."""
    m, g, i_b, i_inv = s.mass, s.gravity, s.inertia, s.i_inv
    r, w, zeta, r_b, height, hess, v_g, wxr = kinematics(s, y)
    zeta_dot = np.cross(zeta, w)
    kappa = r_b @ np.cross(zeta_dot, w) - zeta_dot @ hess @ zeta_dot
    u = np.cross(r_b, zeta)
    gyro = np.cross(w, i_b @ w)
    if s.model == "frictionless":
        d = np.array([0.0, 0.0, 1.0])
        slip = 0.0
    else:
        v_s = v_g + wxr
        v_s[2] = 0.0
        slip = float(np.linalg.norm(v_s))
        d = np.array([0.0, 0.0, 1.0]) - s.friction * v_s / slip
    d_b = r.T @ d
    lever = np.cross(r_b, d_b)
    n = m * (g + u @ i_inv @ gyro - kappa) / (1.0 + m * u @ i_inv @ lever)
    w_dot = i_inv @ (n * lever - gyro)
    qw, qx, qy, qz = y[2:6]
    wx, wy, wz = w
    q_dot = 0.5 * np.array(
        [
            -qx * wx - qy * wy - qz * wz,
            qw * wx + qy * wz - qz * wy,
            qw * wy - qx * wz + qz * wx,
            qw * wz + qx * wy - qy * wx,
        ]
    )
    dy = np.zeros(14)
    dy[0:2] = y[6:8]
    dy[2:6] = q_dot
    dy[6:8] = n * d[0:2] / m
    dy[8:11] = w_dot
    dy[11] = s.friction * n * slip
    return dy


def invariants(s: Scene, y: np.ndarray) -> dict:
    """E, E + W, |p_h|, L_z, omega_3 of one state."""
    r, w, zeta, r_b, height, hess, v_g, wxr = kinematics(s, y)
    lb = s.inertia @ w
    e = 0.5 * s.mass * v_g @ v_g + 0.5 * w @ lb + s.mass * s.gravity * height
    return {
        "energy": e,
        "energy_plus_work": e + y[11],
        "momentum": s.mass * math.hypot(v_g[0], v_g[1]),
        "angular_momentum_z": zeta @ lb,
        "axial_spin": w[2],
    }


def scales(s: Scene, y: np.ndarray, inv: dict) -> dict:
    """The relative-drift scales of crates/ellipsoid-core/src/simulate.rs (`scales`)."""
    r, w, zeta, r_b, height, hess, v_g, wxr = kinematics(s, y)
    lnorm = np.linalg.norm(s.inertia @ w)
    return {
        "energy": abs(inv["energy"]),
        "energy_plus_work": abs(inv["energy_plus_work"]),
        "momentum": s.mass * (np.linalg.norm(v_g) + np.linalg.norm(w) * np.linalg.norm(r_b)),
        "angular_momentum_z": lnorm,
        "axial_spin": np.linalg.norm(w),
    }


def conserved(s: Scene) -> list[str]:
    if s.model == "frictionless":
        return ["energy", "momentum", "angular_momentum_z", "axial_spin"]
    return ["energy_plus_work"]


def ellipsoid(binary: Path, *args: str) -> str:
    """Runs our command-line tool; returns its standard output."""
    out = subprocess.run([str(binary), *args], check=True, capture_output=True, text=True)
    return out.stdout
