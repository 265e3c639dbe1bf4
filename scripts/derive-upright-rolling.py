#!/usr/bin/env python3
"""Derives the linearised upright rolling of a body of revolution (docs/physics.md, "Rims",
"Upright rolling"), independently of the simulator, with Kane's method (sympy.physics.mechanics).

The body rolls without slipping on a parallel at distance rho from G, G in the parallel's
plane, the meridian's radius of curvature there r (a rim: rho = R + r): the contact point
is at -(rho - r) e_down - r e3 from G, e_down the disc plane's downward direction. Angles:
heading q1 about e3, lean q2 about the heading's forward axis, spin q3 about the symmetry
axis; generalised speeds u the angular velocity in the leaning (non-spinning) frame.
Prints the Jacobian about straight rolling (q2 = 0, u = (0, n, 0)) in (q2, u1, u2, u3) and
its characteristic polynomial:
    lam^2 [A (A + m rho^2) lam^2 + C (C + m rho^2) n^2 - A m g (rho - r)] = 0.

Needs sympy (not part of the test venv): python scripts/derive-upright-rolling.py
"""
import sympy as sp
from sympy.physics.mechanics import (KanesMethod, Point, ReferenceFrame, RigidBody,
                                     dynamicsymbols, inertia)

q1, q2, q3, u1, u2, u3 = dynamicsymbols("q1 q2 q3 u1 u2 u3")
q1d, q2d, q3d = dynamicsymbols("q1 q2 q3", 1)
rho, r, m, g, A, C, n = sp.symbols("rho r m g A C n", positive=True)
lam = sp.Symbol("lam")

N = ReferenceFrame("N")
heading = N.orientnew("Y", "Axis", [q1, N.z])
lean = heading.orientnew("L", "Axis", [q2, heading.x])
body_frame = lean.orientnew("B", "Axis", [q3, lean.y])
body_frame.set_ang_vel(N, u1 * lean.x + u2 * lean.y + u3 * lean.z)

contact = Point("C")
contact.set_vel(N, 0)  # rolling: the material point at the contact is at rest
centre = contact.locatenew("G", r * N.z + (rho - r) * lean.z)
centre.v2pt_theory(contact, N, body_frame)

body = RigidBody("body", centre, body_frame, m, (inertia(lean, A, C, A), centre))
rates = q1d * N.z + q2d * lean.x + q3d * lean.y
kinematics = [rates.dot(e) - u for e, u in zip((lean.x, lean.y, lean.z), (u1, u2, u3))]
kane = KanesMethod(N, q_ind=[q1, q2, q3], u_ind=[u1, u2, u3], kd_eqs=kinematics)
kane.kanes_equations([body], [(centre, -m * g * N.z)])
rhs = kane.mass_matrix_full.LUsolve(kane.forcing_full)

state = [q1, q2, q3, u1, u2, u3]
kept = [1, 3, 4, 5]  # q2, u1, u2, u3 (heading and spin angle are cyclic)
steady = {q2: 0, u1: 0, u2: n, u3: 0}
jacobian = sp.simplify(sp.Matrix(4, 4, lambda i, j: sp.diff(rhs[kept[i]], state[kept[j]]).subs(steady)))
sp.pprint(jacobian)
polynomial = sp.factor(sp.simplify(jacobian.charpoly(lam).as_expr()))
print(polynomial)
expected = lam**2 * (A * (A + m * rho**2) * lam**2 + C * (C + m * rho**2) * n**2 - A * m * g * (rho - r))
assert sp.simplify(polynomial * A * (A + m * rho**2) - expected) == 0
print("n_c^2 =", sp.solve(C * (C + m * rho**2) * n**2 - A * m * g * (rho - r), n**2)[0])
