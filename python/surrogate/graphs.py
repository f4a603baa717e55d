"""Graph datasets (docs/datasets.md) as training samples: one run is a Trajectory, the
particles the nodes and the directed bonds the edges, in scaled units (docs/surrogates.md):

    u* = u / (s0 delta)    v* = v / (s0 c)    t* = t c / delta    b* = b delta / (E s0)

with s0 the critical stretch, delta the horizon and c = sqrt(E / rho) of the run's material.
In these units the elastic response of a plate of any material to a traction of a given
multiple of E s0 differs only by the Poisson ratio, which is what lets a model trained on
some materials predict others. Needs NumPy and h5py only."""
import csv
import os

import numpy as np

try:
    import h5py
except ImportError:  # Debian python3-h5py
    h5py = None

NODE_FEATURES = 5    # v* (2), b* (2), damage
EDGE_FEATURES = 10   # (y_j - y_i)/delta (2), |y|/delta, |xi|/delta, (u_j - u_i)* (2), stretch/s0, broken,
                     # the bond force direction (stretch/s0) y/|y| of an intact bond (2)
GLOBAL_FEATURES = 5  # Poisson ratio, frame interval t*, load factor, log10 E/GPa, log10 rho/(1000 kg/m^3)
TARGETS = 4          # next-step change of u* (2) and v* (2)


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


class Trajectory:
    """One run's graph dataset in scaled units: frames of u*, v*, b*, damage and broken flags."""

    def __init__(self, path):
        if h5py is None:
            raise ImportError("h5py is missing: install python3-h5py (scripts/install-deps)")
        self.path = path
        with h5py.File(path, "r") as h5:
            if _text(h5.attrs.get("format", "")) != "peri graph dataset":
                raise ValueError(f"{path}: not a peri graph dataset (docs/datasets.md)")
            g = h5["globals"].attrs
            self.dim = int(g["dimension"])
            if self.dim != 2:
                raise ValueError(f"{path}: the surrogate models take 2D runs, this one is {self.dim}D")
            self.delta, self.spacing = float(g["horizon"]), float(g["spacing"])
            self.rule = _text(g["partial_volume"])
            self.tags = {k: (_text(v) if isinstance(v, (bytes, str)) else float(v)) for k, v in h5["globals/tags"].attrs.items()}
            self.x = h5["nodes/x"][:, :2]
            self.volume = h5["nodes/volume"][...]
            material = h5["nodes/material"][...]
            self.no_fail = h5["nodes/no_fail"][...].astype(bool)
            self.receiver = h5["edges/receiver"][...].astype(np.int64)
            self.sender = h5["edges/sender"][...].astype(np.int64)
            mats = h5["materials"]
            E, nu, rho, s0 = (mats[k][...] for k in ("youngs_modulus", "poisson_ratio", "density", "critical_stretch"))
            # the run's scales: its (first node's) material; the generator's runs have one
            m = int(material[0]) if len(material) else 0
            self.E, self.nu, self.rho, self.s0 = float(E[m]), float(nu[m]), float(rho[m]), float(s0[m])
            self.c = (self.E / self.rho) ** 0.5
            # a bond breaks past the smaller critical stretch of its ends, never at a no-fail end
            self.edge_s0 = np.minimum(s0[material[self.receiver]], s0[material[self.sender]])
            self.edge_s0[self.no_fail[self.receiver] | self.no_fail[self.sender]] = np.inf
            keys = sorted(h5["frames"].keys())
            self.time = np.array([float(h5[f"frames/{k}"].attrs["time"]) for k in keys])
            self.u = np.stack([h5[f"frames/{k}/u"][:, :2] for k in keys]) / (self.s0 * self.delta)
            self.v = np.stack([h5[f"frames/{k}/v"][:, :2] for k in keys]) / (self.s0 * self.c)
            self.b = np.stack([h5[f"frames/{k}/b"][:, :2] for k in keys]) * self.delta / (self.E * self.s0)
            self.damage = np.stack([h5[f"frames/{k}/damage"][...] for k in keys])
            self.broken = np.stack([h5[f"frames/{k}/broken"][...] for k in keys]).astype(bool)
        self.xi = self.x[self.sender] - self.x[self.receiver]
        self.r0 = np.linalg.norm(self.xi, axis=1)
        # the damage index's weights beta V_sender (docs/model_reference.md 7.3)
        beta = np.ones_like(self.r0)
        if self.rule != "none":
            beta = np.clip(0.5 + (self.delta - self.r0) / self.spacing, 0.0, 1.0)
        self.bond_weight = beta * self.volume[self.sender]
        self.family_weight = np.bincount(self.receiver, weights=self.bond_weight, minlength=len(self.x))
        self.dt = float(np.mean(np.diff(self.time))) * self.c / self.delta if len(self.time) > 1 else 0.0
        load = self.tags.get("load_factor", 0.0)
        self.globals = np.array([self.nu, self.dt, load if isinstance(load, float) else 0.0,
                                 np.log10(self.E / 1e9), np.log10(self.rho / 1e3)])

    @property
    def frames(self):
        return len(self.time)

    def families(self):
        """The per-family subgraphs of seed 004 section 8.3: node i's family is edges
        offset[i] .. offset[i+1]-1 (all with receiver i, bonds in CSR order), its nodes i and
        the senders of those edges. The models aggregate each family's edges onto its node."""
        return np.searchsorted(self.receiver, np.arange(len(self.x) + 1))

    def stretch_of(self, u_scaled):
        """Bond stretch of scaled displacements u* (the PD definition, (|y| - |xi|)/|xi|)."""
        y = self.xi + (u_scaled[self.sender] - u_scaled[self.receiver]) * (self.s0 * self.delta)
        return (np.linalg.norm(y, axis=1) - self.r0) / self.r0

    def damage_of(self, broken):
        """Damage index 1 - sum intact beta V / sum beta V of every node."""
        intact = np.bincount(self.receiver, weights=self.bond_weight * ~broken, minlength=len(self.x))
        return 1.0 - intact / np.maximum(self.family_weight, 1e-300)

    def features(self, u, v, b, damage, broken):
        """Node, edge and global input features of a state (scaled arrays)."""
        du = u[self.sender] - u[self.receiver]
        y = self.xi / self.delta + du * self.s0
        stretch = self.stretch_of(u)
        nodes = np.concatenate([v, b, damage[:, None]], axis=1)
        r = np.linalg.norm(y, axis=1, keepdims=True)
        # the seed's dynamic graph carries the PD force of each bond: here its direction and
        # size up to the constant c beta V, (s/s0) y/|y|, zero once broken
        force = np.where(broken[:, None], 0.0, (stretch / self.s0)[:, None] * y / np.maximum(r, 1e-300))
        edges = np.concatenate([y, r, (self.r0 / self.delta)[:, None], du, (stretch / self.s0)[:, None],
                                broken[:, None].astype(float), force], axis=1)
        return nodes, edges, self.globals

    def baseline(self, v):
        """Constant velocity: u*_{t+1} - u*_t = dt* v*_t, v*_{t+1} - v*_t = 0."""
        return np.concatenate([self.dt * v, np.zeros_like(v)], axis=1)

    def target(self, t):
        """Next-step change of u* and v* from frame t to t + 1."""
        return np.concatenate([self.u[t + 1] - self.u[t], self.v[t + 1] - self.v[t]], axis=1)


def load_split(folder, split):
    """The trajectories of one split (train or test) listed in folder/manifest.csv."""
    with open(os.path.join(folder, "manifest.csv"), newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["split"] == split]
    paths = [os.path.join(folder, r["file"]) for r in rows]
    missing = [p for p in paths if not os.path.exists(p)]
    if missing:
        raise FileNotFoundError(f"{len(missing)} runs of the {split} split have no dataset yet (first: {missing[0]}); "
                                "run the generator again to finish the batch")
    return [Trajectory(p) for p in paths]
