#!/usr/bin/env python3
"""A straightforward NumPy re-implementation of Peridigm's explicit update with the `Elastic`
material and the `Critical Stretch` damage model (read from Peridigm's elastic.cxx,
material_utilities.cxx, Peridigm_CriticalStretchDamageModel.cpp and its Verlet loop), for the
fragmenting cylinder:

- families: every j with |x_j - x_i| <= delta, built once; influence omega = 1;
- weighted volume m_i = sum_j omega |xi|^2 V_j over the whole family (fixed);
- each step: v += dt/2 a; u += dt v; then the damage model (a bond whose stretch
  (|Y| - |xi|)/|xi| exceeds s_c is broken for good), then the dilatation
  theta_i = (3/m_i) sum_intact omega |xi| e V_j and the force state
  t_ij = omega theta_i (3K/m_i - alpha_i/3) |xi| + alpha_i omega e, alpha_i = 15 mu/m_i,
  f_i += t_ij V_j Y/|Y|, f_j -= t_ij V_i Y/|Y|; then v += dt/2 a (a = f/rho);
- the initial velocity of the example: v_r = 200 - 50((z/0.05) - 1)^2, v_z = 100((z/0.05) - 1).

Reads a node file (x y z block volume) and prints every EVERY steps
  step mean_damage mean_broken_fraction kinetic_energy strain_energy
(damage: 1 - sum_intact V_j / sum V_j per node, averaged over the nodes; kinetic energy
sum rho V v^2/2; strain energy K theta^2/2 + alpha/2 sum omega (e^d)^2 V_j, summed with V_i).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lammps_peri import families  # noqa: E402  (the cell-list search, |xi| <= delta)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("nodes")
    p.add_argument("--horizon", type=float, required=True)
    p.add_argument("--dt", type=float, required=True)
    p.add_argument("--steps", type=int, required=True)
    p.add_argument("--every", type=int, default=10)
    p.add_argument("--K", type=float, default=130.0e9)
    p.add_argument("--mu", type=float, default=78.0e9)
    p.add_argument("--density", type=float, default=7800.0)
    p.add_argument("--critical-stretch", type=float, default=0.02)
    a = p.parse_args()
    data = np.loadtxt(a.nodes, ndmin=2)
    x, vol = data[:, :3], data[:, 4]
    n = len(x)
    I, J = families(x, a.horizon * (1 + 1e-12))
    d0 = x[J] - x[I]
    zeta = np.sqrt(np.einsum("ij,ij->i", d0, d0))
    m = np.bincount(I, zeta * zeta * vol[J], n)
    alpha = 15.0 * a.mu / m
    vol_all = np.bincount(I, vol[J], n)
    intact = np.ones(len(I), bool)
    vr = 200.0 - 50.0 * ((x[:, 2] / 0.05) - 1.0) ** 2
    ang = np.arctan2(x[:, 1], x[:, 0])
    v = np.stack([vr * np.cos(ang), vr * np.sin(ang), 100.0 * ((x[:, 2] / 0.05) - 1.0)], axis=1)
    u = np.zeros_like(x)

    def bonds():
        y = x + u
        Y = y[J] - y[I]
        dY = np.sqrt(np.einsum("ij,ij->i", Y, Y))
        return Y, dY, dY - zeta

    def force(Y, dY, e):
        on = intact
        theta = 3.0 / m * np.bincount(I[on], (zeta * e * vol[J])[on], n)
        t = np.where(on, theta[I] * (3.0 * a.K / m[I] - alpha[I] / 3.0) * zeta + alpha[I] * e, 0.0)
        g = t / np.where(dY > 0, dY, 1.0)
        f = np.zeros((n, 3))
        for c in range(3):
            f[:, c] = np.bincount(I, g * vol[J] * Y[:, c], n) - np.bincount(J, g * vol[I] * Y[:, c], n)
        return f, theta

    def row(step, theta, e):
        on = intact
        phi = 1.0 - np.bincount(I[on], vol[J][on], n) / vol_all
        ke = 0.5 * np.sum(a.density * vol * np.einsum("ij,ij->i", v, v))
        ed = e - theta[I] * zeta / 3.0
        W = 0.5 * a.K * theta ** 2 + 0.5 * alpha * np.bincount(I[on], (ed * ed * vol[J])[on], n)
        return "%d %.17g %.17g %.17g %.17g" % (step, phi.mean(), phi.mean(), ke, np.sum(vol * W))

    Y, dY, e = bonds()
    f, theta = force(Y, dY, e)
    print(row(0, theta, e), flush=True)
    for step in range(1, a.steps + 1):
        v += 0.5 * a.dt * f / a.density
        u += a.dt * v
        Y, dY, e = bonds()  # once a step: the damage model and the force see the same positions
        intact &= ~(e / zeta > a.critical_stretch)  # the damage model, before the force
        f, theta = force(Y, dY, e)
        v += 0.5 * a.dt * f / a.density
        if step % a.every == 0 or step == a.steps:
            print(row(step, theta, e), flush=True)


if __name__ == "__main__":
    main()
