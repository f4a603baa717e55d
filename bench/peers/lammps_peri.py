#!/usr/bin/env python3
"""A straightforward NumPy re-implementation of the LAMMPS PERI update loop (pair peri/pmb and
pair peri/lps with fix peri/neigh, fix nve and fix indent sphere), with the short-range
contact forces of the pair styles on request (--short-range), written from the semantics of LAMMPS's pair_peri_pmb.cpp,
pair_peri_lps.cpp, fix_peri_neigh.cpp and compute_damage_atom.cpp:

- families: every j with |x_j - x_i|^2 <= delta^2 (fix peri/neigh), built once;
- volume scale of bonds near the horizon: vfrac_scale = 1/2 + (delta - r0)/lc when
  |r0 - delta| <= lc/2, else 1 (lc the lattice constant);
- pmb: f_i += c V_j scale s (x_j - x_i)/r;
- lps: theta_i = (3/m_i) sum_intact omega r0 dr V_j scale, m_i = sum omega r0^2 V_j scale
  (omega = 1/r0), f_i += [(3K - 5G) V_j scale (omega theta_i/m_i + omega theta_j/m_j) r0
  + 15 G V_j scale (omega/m_i + omega/m_j) dr] (x_j - x_i)/r;
- |dr| < 2.2204e-16 is taken as 0 (NEAR_ZERO);
- breaking after the force: a bond intact at the start of the evaluation is cut when its
  stretch exceeds min(s0_i, s0_j) of the previous evaluation; then
  s0_i = s00 - alpha min_j s_ij over the bonds intact at the start; s0 starts at DBL_MAX;
- short-range forces (--short-range): every pair closer than d_ij = min(0.9 r0, 1.35 lc),
  bonded or not, f_i += 15 k V_j (d_ij - r)/delta (y_i - y_j)/r with k = c (pmb) or
  18 K/(pi delta^4) (lps), from all pairs of the current positions at every evaluation;
- fix nve (velocity Verlet, mass density rho) and fix indent sphere (force k (R - r)^2
  outward for r < R, centre y0 + vy t at the time of the force).

Reads the node set (x y z volume per line, as bench/peers/peri_series writes it) and prints
every EVERY steps: step mean_damage mean_broken_fraction kinetic_energy strain_energy, with
peri's definitions (mean damage beta-weighted with the same ramp; kinetic energy
sum rho V v^2/2; strain energy of the PMB micropotential or of the LPS energy density).
"""
import argparse
import sys

import numpy as np

NEAR_ZERO = 2.2204e-16


def families(x, cutoff):
    """Directed bonds (i, j) with |x_j - x_i|^2 <= cutoff^2, sorted by i then j (cell list)."""
    lo = x.min(axis=0)
    cell = np.floor((x - lo) / cutoff).astype(np.int64)
    dims = cell.max(axis=0) + 3
    key = ((cell[:, 0] + 1) * dims[1] + (cell[:, 1] + 1)) * dims[2] + (cell[:, 2] + 1)
    order = np.argsort(key, kind="stable")
    skey = key[order]
    I, J = [], []
    for ox in (-1, 0, 1):
        for oy in (-1, 0, 1):
            for oz in (-1, 0, 1):
                k2 = key + (ox * dims[1] + oy) * dims[2] + oz
                a = np.searchsorted(skey, k2, "left")
                b = np.searchsorted(skey, k2, "right")
                cnt = b - a
                ii = np.repeat(np.arange(len(x)), cnt)
                start = np.repeat(a - np.concatenate(([0], np.cumsum(cnt)[:-1])), cnt)
                jj = order[np.arange(cnt.sum()) + start]
                d = x[jj] - x[ii]
                keep = (ii != jj) & (np.einsum("ij,ij->i", d, d) <= cutoff * cutoff)
                I.append(ii[keep])
                J.append(jj[keep])
    I = np.concatenate(I)
    J = np.concatenate(J)
    o = np.lexsort((J, I))
    return I[o], J[o]


class Lammps:
    def __init__(self, x, vol, a):
        self.a = a
        self.x0 = x.copy()
        self.n = len(x)
        self.vol = vol
        self.I, self.J = families(x, a.horizon)
        d0 = x[self.J] - x[self.I]
        self.r0 = np.sqrt(np.einsum("ij,ij->i", d0, d0))
        half_lc = 0.5 * a.lattice
        self.scale = np.where(np.abs(self.r0 - a.horizon) <= half_lc,
                              (-1.0 / (2 * half_lc)) * self.r0 + (1.0 + (a.horizon - half_lc) / (2 * half_lc)), 1.0)
        self.intact = np.ones(len(self.I), bool)
        self.s0 = np.full(self.n, sys.float_info.max)
        self.w = vol[self.J] * self.scale  # vfrac[j] * vfrac_scale
        if a.model == "lps":
            omega = 1.0 / self.r0
            self.m = np.bincount(self.I, omega * self.r0 * self.r0 * self.w, self.n)
        self.u = np.zeros_like(x)
        self.v = np.zeros_like(x)
        # peri's damage index weights (beta from its ramp: min(1, 1/2 + (delta - r0)/dx))
        self.beta_w = np.minimum(1.0, 0.5 + (a.horizon - self.r0) / a.lattice) * vol[self.J]
        self.beta_all = np.bincount(self.I, self.beta_w, self.n)
        self.count_all = np.bincount(self.I, minlength=self.n).astype(float)

    def bonds(self):
        y = self.x0 + self.u
        d = y[self.J] - y[self.I]
        r = np.sqrt(np.einsum("ij,ij->i", d, d))
        dr = r - self.r0
        dr[np.abs(dr) < NEAR_ZERO] = 0.0
        return d, r, dr

    def force(self, t):
        a, I, J, on = self.a, self.I, self.J, self.intact
        d, r, dr = self.bonds()
        stretch = dr / self.r0
        if a.model == "pmb":
            rk = a.c * self.w * stretch
        else:
            omega = 1.0 / self.r0
            theta = np.bincount(I[on], (omega * self.r0 * dr * self.w)[on], self.n)
            theta = np.where(self.m != 0.0, 3.0 / np.where(self.m != 0, self.m, 1) * theta, 0.0)
            rk = (3.0 * a.K - 5.0 * a.G) * self.w * (omega * theta[I] / self.m[I] + omega * theta[J] / self.m[J]) * self.r0
            rk = rk + 15.0 * (a.G * self.w) * (omega / self.m[I] + omega / self.m[J]) * dr
        fb = np.where(r > 0.0, rk / np.where(r > 0, r, 1), 0.0)
        fb[~on] = 0.0
        f = np.zeros((self.n, 3))
        for c in range(3):
            f[:, c] = np.bincount(I, fb * d[:, c], self.n)
        # after the force: the cut with the previous s0, then the new s0
        cut = on & (stretch > np.minimum(self.s0[I], self.s0[J]))
        smin = np.full(self.n, np.inf)
        np.minimum.at(smin, I[on], stretch[on])
        self.intact = on & ~cut
        has = np.isfinite(smin)
        self.s0[has] = a.s00 - a.alpha * smin[has]
        if a.short_range:
            f += self.short_range()
        # fix indent sphere
        if a.indenter_radius > 0:
            c = np.array([a.indenter_x, a.indenter_y0 + a.indenter_vy * t, a.indenter_z])
            dx = self.x0 + self.u - c
            rr = np.sqrt(np.einsum("ij,ij->i", dx, dx))
            dR = rr - a.indenter_radius
            hit = dR < 0.0
            f[hit] += dx[hit] * (a.indenter_k * dR[hit] ** 2 / rr[hit])[:, None]
        return f

    def short_range(self):
        a = self.a
        y = self.x0 + self.u
        reach = 1.35 * a.lattice
        I, J = families(y, reach)
        d0 = self.x0[I] - self.x0[J]
        dij = np.minimum(0.9 * np.sqrt(np.einsum("ij,ij->i", d0, d0)), reach)
        d = y[I] - y[J]
        r = np.sqrt(np.einsum("ij,ij->i", d, d))
        hit = (r < dij) & (r > 0.0)
        k = a.c if a.model == "pmb" else 18.0 * a.K / (np.pi * a.horizon ** 4)
        g = np.zeros(len(I))
        g[hit] = 15.0 * k * self.vol[J[hit]] * (dij[hit] - r[hit]) / (a.horizon * r[hit])
        f = np.zeros((self.n, 3))
        for c in range(3):
            f[:, c] = np.bincount(I, g * d[:, c], self.n)
        return f

    def row(self, step):
        I, on = self.I, self.intact
        phi = 1.0 - np.bincount(I[on], self.beta_w[on], self.n) / self.beta_all
        frac = 1.0 - np.bincount(I[on], minlength=self.n) / self.count_all
        ke = 0.5 * np.sum(self.a.density * self.vol * np.einsum("ij,ij->i", self.v, self.v))
        return "%d %.17g %.17g %.17g %.17g" % (step, phi.mean(), frac.mean(), ke, self.strain_energy())

    def strain_energy(self):
        a, I, on = self.a, self.I, self.intact
        d, r, dr = self.bonds()
        if a.model == "pmb":
            s = dr / self.r0
            W = 0.5 * np.bincount(I[on], (0.5 * a.c * s * s * self.r0 * self.w)[on], self.n)
        else:  # peri's LPS energy density with its ramp (docs/models.md 3.1)
            omega = 1.0 / self.r0
            theta = 3.0 / self.m * np.bincount(I[on], (omega * self.r0 * dr * self.w)[on], self.n)
            ed = dr - theta[I] * self.r0 / 3.0
            W = 0.5 * a.K * theta ** 2 + 0.5 * (15.0 * a.G / self.m) * np.bincount(I[on], (omega * ed * ed * self.w)[on], self.n)
        return float(np.sum(self.vol * W))

    def run(self, out):
        a = self.a
        dt = a.dt
        f = self.force(0.0)
        print(self.row(0), file=out, flush=True)
        for step in range(1, a.steps + 1):
            self.v += 0.5 * dt * f / a.density
            self.u += dt * self.v
            f = self.force(step * dt)
            self.v += 0.5 * dt * f / a.density
            if step % a.every == 0:
                print(self.row(step), file=out, flush=True)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("nodes")
    p.add_argument("--model", choices=["pmb", "lps"], required=True)
    p.add_argument("--horizon", type=float, default=0.0015001)
    p.add_argument("--lattice", type=float, default=0.0005)
    p.add_argument("--c", type=float, default=1.6863e22, help="pmb micromodulus")
    p.add_argument("--K", type=float, default=14.9e9)
    p.add_argument("--G", type=float, default=14.9e9)
    p.add_argument("--s00", type=float, default=0.0005)
    p.add_argument("--alpha", type=float, default=0.25)
    p.add_argument("--density", type=float, default=2200.0)
    p.add_argument("--dt", type=float, default=1.0e-7)
    p.add_argument("--steps", type=int, default=1000)
    p.add_argument("--every", type=int, default=100)
    p.add_argument("--indenter-radius", type=float, default=0.0015)
    p.add_argument("--indenter-k", type=float, default=1.0e17)
    p.add_argument("--indenter-x", type=float, default=0.0)
    p.add_argument("--indenter-y0", type=float, default=0.00155)
    p.add_argument("--indenter-vy", type=float, default=-100.0)
    p.add_argument("--indenter-z", type=float, default=0.0)
    p.add_argument("--short-range", action="store_true", help="the pair styles' short-range forces")
    a = p.parse_args()
    nodes = np.loadtxt(a.nodes, ndmin=2)
    Lammps(nodes[:, :3], nodes[:, 3], a).run(sys.stdout)


if __name__ == "__main__":
    main()
