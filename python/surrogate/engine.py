"""What training and evaluation share: tensors of a trajectory's graph, the model's step
from a state, and the rollout that feeds predictions back (the broken bonds follow the PD
rule: a bond breaks for good when its predicted stretch passes its critical stretch)."""
import numpy as np
import torch

from .models import KINDS

OBSERVED_FRAMES = 3  # frames the inference model reads before it predicts


def device_of(name=None):
    """CUDA when present (or asked for), else the CPU."""
    if name:
        return torch.device(name)
    return torch.device("cuda" if torch.cuda.is_available() else "cpu")


class Graph:
    """A trajectory's edge index on the device."""

    def __init__(self, traj, device):
        self.traj, self.device = traj, device
        self.receiver = torch.as_tensor(traj.receiver, device=device)
        self.sender = torch.as_tensor(traj.sender, device=device)

    def inputs(self, u, v, b, damage, broken):
        nodes, edges, glob = self.traj.features(u, v, b, damage, broken)
        t = lambda a: torch.as_tensor(np.asarray(a, dtype=np.float32), device=self.device)
        return t(edges), t(nodes), t(glob)[None, :], t(self.traj.baseline(v))

    def frame_inputs(self, k):
        tr = self.traj
        return self.inputs(tr.u[k], tr.v[k], tr.b[k], tr.damage[k], tr.broken[k])


def build(kind, cfg):
    if kind not in KINDS:
        raise ValueError(f"unknown model '{kind}' (choose from {', '.join(KINDS)})")
    return KINDS[kind](cfg)


def observe(model, graph, first=0):
    """The inference model's summary G'(T) of frames first .. first + OBSERVED_FRAMES - 1."""
    obs = [graph.frame_inputs(k)[:3] for k in range(first, first + OBSERVED_FRAMES)]
    return model.observe(obs, graph.receiver, graph.sender)


def step(model, kind, graph, inputs, scale, memory):
    """One predicted step: (change of u*, v* as an [n, 4] tensor, the next memory)."""
    e, v, g, base = inputs
    if kind == "forward":
        return model(e, v, g, graph.receiver, graph.sender, base, scale), None
    if kind == "recurrent":
        if memory is None:
            memory = model.initial_state(e.shape[0], v.shape[0], e.device)
        return model(e, v, g, graph.receiver, graph.sender, base, scale, memory)
    return model(e, v, g, graph.receiver, graph.sender, base, scale, memory), memory  # inference: summary


def first_frame(kind):
    """The first frame a model can predict from (the inference model first observes)."""
    return OBSERVED_FRAMES - 1 if kind == "inference" else 0


@torch.no_grad()
def rollout(model, kind, graph, scale, start, steps, baseline=False):
    """Predicted u*, v*, damage of frames start+1 .. start+steps, from the PD state at
    `start` (the external loads b* are the run's, known in advance)."""
    tr = graph.traj
    u, v = tr.u[start].copy(), tr.v[start].copy()
    broken = tr.broken[start].copy()
    memory = observe(model, graph) if kind == "inference" and not baseline else None
    out_u, out_v, out_d = [], [], []
    for k in range(start, start + steps):
        if baseline:
            delta = tr.baseline(v)
        else:
            delta, memory = step(model, kind, graph, graph.inputs(u, v, tr.b[k], tr.damage_of(broken), broken), scale,
                                 memory)
            delta = delta.cpu().numpy().astype(np.float64)
        u, v = u + delta[:, :2], v + delta[:, 2:]
        broken = broken | (tr.stretch_of(u) > tr.edge_s0)
        out_u.append(u), out_v.append(v), out_d.append(tr.damage_of(broken))
    return np.array(out_u), np.array(out_v), np.array(out_d)


def load_checkpoint(path, device):
    ck = torch.load(path, map_location=device)
    model = build(ck["kind"], ck["cfg"]).to(device)
    model.load_state_dict(ck["model"])
    model.eval()
    return model, ck
