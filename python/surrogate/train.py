"""Training of the graph-network surrogates (docs/surrogates.md): next-step L2 loss on the
scaled displacement and velocity, with noise injected into the input state for stable
rollouts, Adam, checkpoints after every epoch (and --resume).

    python3 -m surrogate.train --data DATASET --model forward --minutes 8 --out model.pt"""
import argparse
import os
import random
import sys
import time

import numpy as np
import torch

from . import engine
from .graphs import load_split
from .models import DEFAULTS


def target_scale(trajs):
    """Per-channel RMS of the next-step changes of u* and v* over the training frames: the
    loss is the MSE in these units (docs/surrogates.md)."""
    d = np.concatenate([np.concatenate([t.target(k) for k in range(t.frames - 1)]) for t in trajs])
    rms = np.sqrt(np.mean(d ** 2, axis=0))
    return np.where(rms > 0, rms, 1.0)


def noisy(traj, k, noise, scale, rng):
    """Frame k's u*, v* with Gaussian noise of `noise` times the step scale (Sanchez-Gonzalez
    2020): the model learns to step from slightly wrong states, as in its own rollouts."""
    u = traj.u[k] + rng.normal(0.0, noise * scale[0], traj.u[k].shape) if noise > 0 else traj.u[k]
    v = traj.v[k] + rng.normal(0.0, noise * scale[2], traj.v[k].shape) if noise > 0 else traj.v[k]
    return u, v


def train(data, kind="forward", cfg=None, epochs=100, minutes=None, lr=1e-3, noise=0.1, batch=4, sequence=4,
          out=None, resume=False, seed=0, device=None, log=sys.stderr):
    """Trains on the train split of `data` and returns (model, checkpoint dict)."""
    torch.manual_seed(seed)
    rng, pick = np.random.default_rng(seed), random.Random(seed)
    device = engine.device_of(device)
    trajs = load_split(data, "train")
    graphs = [engine.Graph(t, device) for t in trajs]
    cfg = dict(DEFAULTS, **(cfg or {}))
    model = engine.build(kind, cfg).to(device)
    opt = torch.optim.Adam(model.parameters(), lr=lr)
    scale_np = target_scale(trajs)
    scale = torch.as_tensor(scale_np, dtype=torch.float32, device=device)
    first_epoch = 0
    if resume and out and os.path.exists(out):
        ck = torch.load(out, map_location=device)
        model.load_state_dict(ck["model"])
        opt.load_state_dict(ck["optimizer"])
        first_epoch = ck["epoch"]
    first = engine.first_frame(kind)
    length = sequence if kind == "recurrent" else 1
    samples = [(g, k) for g in graphs for k in range(first, g.traj.frames - length)]
    if not samples:
        raise ValueError("no training samples: the runs have too few frames")
    t0, seen, ck = time.time(), 0, None
    print(f"training {kind} on {len(trajs)} runs, {len(samples)} samples, {sum(p.numel() for p in model.parameters())} "
          f"parameters, on {device}", file=log)
    for epoch in range(first_epoch, epochs):
        pick.shuffle(samples)
        total, count = 0.0, 0
        model.train()
        for n, (g, k) in enumerate(samples):
            memory = engine.observe(model, g) if kind == "inference" else None
            loss = 0.0
            for j in range(k, k + length):  # one step, or a sequence (the recurrent model)
                u, v = noisy(g.traj, j, noise, scale_np, rng)
                tr = g.traj
                pred, memory = engine.step(model, kind, g, g.inputs(u, v, tr.b[j], tr.damage[j], tr.broken[j]), scale,
                                           memory)
                target = np.concatenate([tr.u[j + 1] - u, tr.v[j + 1] - v], axis=1)
                target = torch.as_tensor(target, dtype=torch.float32, device=device)
                loss = loss + torch.mean(((pred - target) / scale) ** 2) / length
            (loss / batch).backward()
            total, count, seen = total + float(loss), count + 1, seen + 1
            if (n + 1) % batch == 0 or n + 1 == len(samples):
                opt.step()
                opt.zero_grad()
            if minutes and time.time() - t0 > 60 * minutes:
                break
        for group in opt.param_groups:  # a slow decay: 0.1 over ~45 epochs
            group["lr"] *= 0.95
        elapsed = time.time() - t0
        print(f"epoch {epoch + 1}: loss {total / max(count, 1):.4g} (scaled MSE), {seen / elapsed:.1f} samples/s, "
              f"{elapsed:.0f} s", file=log)
        ck = {"kind": kind, "cfg": cfg, "model": model.state_dict(), "optimizer": opt.state_dict(), "scale": scale_np,
              "epoch": epoch + 1, "samples_per_second": seen / elapsed, "seconds": elapsed, "loss": total / max(count, 1)}
        if out:
            torch.save(ck, out + ".tmp")
            os.replace(out + ".tmp", out)
        if minutes and elapsed > 60 * minutes:
            break
    model.eval()
    return model, ck


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--data", required=True, help="dataset folder of surrogate.generate (manifest.csv)")
    p.add_argument("--model", default="forward", choices=["forward", "recurrent", "inference"])
    p.add_argument("--out", required=True, help="checkpoint file")
    p.add_argument("--epochs", type=int, default=100)
    p.add_argument("--minutes", type=float, default=None, help="stop after this much training time")
    p.add_argument("--lr", type=float, default=1e-3)
    p.add_argument("--noise", type=float, default=0.1, help="input noise, in units of the step scale")
    p.add_argument("--batch", type=int, default=4, help="graphs per optimizer step")
    p.add_argument("--resume", action="store_true", help="continue from --out")
    p.add_argument("--device", default=None, help="cpu or cuda (default: cuda when present)")
    p.add_argument("--threads", type=int, default=None, help="CPU threads of PyTorch")
    for key, value in DEFAULTS.items():
        p.add_argument("--" + key.replace("_", "-"), type=int, default=value, help=f"(seed 004 section 8.3: {value})")
    a = p.parse_args(argv)
    if a.threads:
        torch.set_num_threads(a.threads)
    cfg = {k: getattr(a, k) for k in DEFAULTS}
    train(a.data, a.model, cfg, a.epochs, a.minutes, a.lr, a.noise, a.batch, out=a.out, resume=a.resume,
          device=a.device)
    return 0


if __name__ == "__main__":
    sys.exit(main())
