"""Rollout evaluation of a trained surrogate (docs/surrogates.md): one-step and K-step
trajectory MSE of the scaled displacement u* = u/(s0 delta) and velocity v* = v/(s0 c) on a
split, beside the constant-velocity baseline, and damage maps, PD above the surrogate, at
chosen rollout steps.

    python3 -m surrogate.evaluate --data DATASET --checkpoint model.pt --steps 10 --pictures out/"""
import argparse
import json
import os
import sys

import numpy as np
import torch

from . import engine, png
from .graphs import load_split


@torch.no_grad()
def one_step(model, kind, graphs, scale, baseline=False):
    """MSE of u* and v* over every predictable frame of every run (teacher-forced states)."""
    eu, ev, n = 0.0, 0.0, 0
    for g in graphs:
        tr = g.traj
        memory = engine.observe(model, g) if kind == "inference" and not baseline else None
        for k in range(engine.first_frame(kind), tr.frames - 1):
            if baseline:
                d = tr.baseline(tr.v[k])
            else:
                d, memory = engine.step(model, kind, g, g.frame_inputs(k), scale, memory)
                d = d.cpu().numpy().astype(np.float64)
            eu += np.mean((tr.u[k] + d[:, :2] - tr.u[k + 1]) ** 2)
            ev += np.mean((tr.v[k] + d[:, 2:] - tr.v[k + 1]) ** 2)
            n += 1
    return eu / n, ev / n


def rollout_errors(model, kind, graphs, scale, steps, baseline=False):
    """MSE of u* and v* over `steps` rollout steps from the first predictable frame, and the
    mean absolute damage error at the last of them."""
    eu, ev, ed, su, sv = [], [], [], [], []
    for g in graphs:
        tr = g.traj
        start = engine.first_frame(kind)
        k = min(steps, tr.frames - 1 - start)
        u, v, d = engine.rollout(model, kind, g, scale, start, k, baseline)
        eu.append(np.mean((u - tr.u[start + 1:start + 1 + k]) ** 2))
        ev.append(np.mean((v - tr.v[start + 1:start + 1 + k]) ** 2))
        su.append(np.mean(tr.u[start + 1:start + 1 + k] ** 2))
        sv.append(np.mean(tr.v[start + 1:start + 1 + k] ** 2))
        ed.append(np.mean(np.abs(d[-1] - tr.damage[start + k])))
    # also relative: the MSE over the mean square of the PD trajectory
    return float(np.mean(eu)), float(np.mean(ev)), float(np.mean(ed)), float(np.sum(eu) / np.sum(su)), \
        float(np.sum(ev) / np.sum(sv))


def damage_pictures(model, kind, graphs, scale, at_steps, folder):
    """folder/<run>_damage.png: PD damage (top row) and predicted (bottom) at the steps."""
    os.makedirs(folder, exist_ok=True)
    written = []
    for g in graphs:
        tr = g.traj
        start = engine.first_frame(kind)
        last = min(max(at_steps), tr.frames - 1 - start)
        _, _, d = engine.rollout(model, kind, g, scale, start, last)
        steps = [s for s in at_steps if 1 <= s <= last]
        pd_row = [png.node_image(tr.x, tr.spacing, tr.damage[start + s]) for s in steps]
        gn_row = [png.node_image(tr.x, tr.spacing, d[s - 1]) for s in steps]
        name = os.path.relpath(tr.path, os.path.dirname(os.path.dirname(os.path.dirname(tr.path))))
        path = os.path.join(folder, os.path.dirname(name).replace(os.sep, "_") + "_damage.png")
        png.write(path, png.grid([pd_row, gn_row]))
        written.append(path)
    return written


def evaluate(data, checkpoint, split="test", steps=10, pictures=None, at=(1, 5, 10), device=None):
    device = engine.device_of(device)
    model, ck = engine.load_checkpoint(checkpoint, device)
    kind = ck["kind"]
    scale = torch.as_tensor(ck["scale"], dtype=torch.float32, device=device)
    graphs = [engine.Graph(t, device) for t in load_split(data, split)]
    out = {"split": split, "runs": len(graphs), "model": kind, "epochs": ck["epoch"]}
    out["one_step_u"], out["one_step_v"] = one_step(model, kind, graphs, scale)
    out["baseline_one_step_u"], out["baseline_one_step_v"] = one_step(model, kind, graphs, scale, baseline=True)
    out["rollout_steps"] = steps
    (out["rollout_u"], out["rollout_v"], out["rollout_damage"], out["rollout_u_relative"],
     out["rollout_v_relative"]) = rollout_errors(model, kind, graphs, scale, steps)
    (out["baseline_rollout_u"], out["baseline_rollout_v"], out["baseline_rollout_damage"],
     out["baseline_rollout_u_relative"], out["baseline_rollout_v_relative"]) = rollout_errors(
        model, kind, graphs, scale, steps, baseline=True)
    if pictures:
        out["pictures"] = damage_pictures(model, kind, graphs, scale, list(at), pictures)
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--data", required=True)
    p.add_argument("--checkpoint", required=True)
    p.add_argument("--split", default="test", choices=["train", "test"])
    p.add_argument("--steps", type=int, default=10, help="rollout length (frames)")
    p.add_argument("--pictures", default=None, help="folder for the damage maps")
    p.add_argument("--at", default="1,5,10", help="rollout steps of the damage maps")
    p.add_argument("--device", default=None)
    a = p.parse_args(argv)
    result = evaluate(a.data, a.checkpoint, a.split, a.steps, a.pictures, [int(s) for s in a.at.split(",")], a.device)
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
