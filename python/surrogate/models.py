"""Graph networks of Ebrahimi 2020 (seed 004) chapter 8: the GN block of its Algorithm 7
(edge, node and global MLPs, eq. 8.3), the forward model of two stacked GN blocks, its
recurrent version, and the recurrent inference model whose summary of an observed
trajectory is fed to the forward model. Default sizes are those of section 8.3: edge MLP
2 hidden layers of 256, node and global MLPs 2 hidden layers of 128, updated edge, node and
global size 128, state graph (recurrent models) 20 per edge, node and global."""
import torch
from torch import nn

from .graphs import EDGE_FEATURES, GLOBAL_FEATURES, NODE_FEATURES, TARGETS

DEFAULTS = {"edge_hidden": 256, "node_hidden": 128, "global_hidden": 128, "latent": 128, "state": 20, "layers": 2}


def mlp(n_in, hidden, layers, n_out):
    """`layers` hidden layers of `hidden` ReLU units, a linear output."""
    mods, width = [], n_in
    for _ in range(layers):
        mods += [nn.Linear(width, hidden), nn.ReLU()]
        width = hidden
    mods.append(nn.Linear(width, n_out))
    return nn.Sequential(*mods)


def family_sum(values, index, count):
    """rho^{e->v}: the sum of each family's edge rows, divided by the largest family's size
    (a constant of the graph): a node that lost neighbours (a surface, a crack) gets a
    smaller sum, as its PD force does, at the scale of a mean."""
    total = torch.zeros(count, values.shape[1], dtype=values.dtype, device=values.device).index_add_(0, index, values)
    largest = torch.bincount(index, minlength=count).max().clamp(min=1)
    return total / largest.to(values.dtype)


class EdgeMLP(nn.Module):
    """phi_e of [e, v_r, v_s, g]: the first layer's product is split by input, W_e e +
    (W_r v)[r] + (W_s v)[s] + W_g g, the same function with the node and global terms
    computed once per node and once per graph instead of once per edge."""

    def __init__(self, e_in, v_in, g_in, hidden, layers, n_out):
        super().__init__()
        self.w_e, self.w_r = nn.Linear(e_in, hidden), nn.Linear(v_in, hidden, bias=False)
        self.w_s, self.w_g = nn.Linear(v_in, hidden, bias=False), nn.Linear(g_in, hidden, bias=False)
        self.rest = mlp(hidden, hidden, layers - 1, n_out)

    def forward(self, e, v, g, receiver, sender):
        h = self.w_e(e) + self.w_r(v)[receiver] + self.w_s(v)[sender] + self.w_g(g)
        return self.rest(torch.relu(h))


class GNBlock(nn.Module):
    """One graph2graph pass (Algorithm 7): e'_k = phi_e(e_k, v_rk, v_sk, g); v'_i =
    phi_v(family sum of e' (family_sum), v_i, g); g' = phi_g(mean e', mean v', g)."""

    def __init__(self, e_in, v_in, g_in, e_out, v_out, g_out, cfg):
        super().__init__()
        layers = cfg["layers"]
        self.phi_e = EdgeMLP(e_in, v_in, g_in, cfg["edge_hidden"], layers, e_out)
        self.phi_v = mlp(e_out + v_in + g_in, cfg["node_hidden"], layers, v_out)
        self.phi_g = mlp(e_out + v_out + g_in, cfg["global_hidden"], layers, g_out)

    def forward(self, e, v, g, receiver, sender):
        n_nodes = v.shape[0]
        e2 = self.phi_e(e, v, g, receiver, sender)
        v2 = self.phi_v(torch.cat([family_sum(e2, receiver, n_nodes), v, g.expand(n_nodes, -1)], dim=1))
        g2 = self.phi_g(torch.cat([e2.mean(0, keepdim=True), v2.mean(0, keepdim=True), g], dim=1))
        return e2, v2, g2


class ForwardModel(nn.Module):
    """Two stacked GN blocks (Fig. 8.3c): the first encodes the dynamic graph G_d with the
    static globals, the second, fed with its output and G_d again, lets every node hear the
    others through the global; a node MLP decodes the next-step change of (u*, v*). The
    prediction is the constant-velocity step plus that change, whose last layer starts at
    zero: the untrained model is the baseline. `extra` = (edge, node, global) widths of
    inputs concatenated to G_d (the recurrent state, or the inference model's summary)."""

    def __init__(self, cfg=None, extra=(0, 0, 0)):
        super().__init__()
        self.cfg = cfg = dict(DEFAULTS, **(cfg or {}))
        L = cfg["latent"]
        ei, vi, gi = EDGE_FEATURES + extra[0], NODE_FEATURES + extra[1], GLOBAL_FEATURES + extra[2]
        self.gn1 = GNBlock(ei, vi, gi, L, L, L, cfg)
        self.gn2 = GNBlock(L + ei, L + vi, L + gi, L, L, L, cfg)
        # the decoder reads the second block's nodes and, as a skip, the inputs: each node's
        # own features and its family's summed edge features (which hold the PD force)
        self.decode = mlp(L + vi + ei, cfg["node_hidden"], cfg["layers"], TARGETS)
        nn.init.zeros_(self.decode[-1].weight)
        nn.init.zeros_(self.decode[-1].bias)

    def latent(self, e, v, g, receiver, sender):
        e1, v1, g1 = self.gn1(e, v, g, receiver, sender)
        return self.gn2(torch.cat([e1, e], 1), torch.cat([v1, v], 1), torch.cat([g1, g], 1), receiver, sender)

    def decode_nodes(self, v2, e, v, receiver):
        return self.decode(torch.cat([v2, v, family_sum(e, receiver, v.shape[0])], dim=1))

    def forward(self, e, v, g, receiver, sender, baseline, scale):
        _, v2, _ = self.latent(e, v, g, receiver, sender)
        return baseline + self.decode_nodes(v2, e, v, receiver) * scale


class RecurrentForwardModel(nn.Module):
    """The recurrent version (Fig. 8.3d): the forward model reads G_d concatenated with a
    hidden state graph G_h (`state` features per edge, node and global) and also returns the
    next G_h, so that it carries a memory along the trajectory."""

    def __init__(self, cfg=None):
        super().__init__()
        self.cfg = cfg = dict(DEFAULTS, **(cfg or {}))
        S, L = cfg["state"], cfg["latent"]
        self.core = ForwardModel(cfg, extra=(S, S, S))
        self.state_e, self.state_v, self.state_g = nn.Linear(L, S), nn.Linear(L, S), nn.Linear(L, S)

    def initial_state(self, n_edges, n_nodes, device):
        S = self.cfg["state"]
        return (torch.zeros(n_edges, S, device=device), torch.zeros(n_nodes, S, device=device),
                torch.zeros(1, S, device=device))

    def forward(self, e, v, g, receiver, sender, baseline, scale, state):
        he, hv, hg = state
        e, v, g = torch.cat([e, he], 1), torch.cat([v, hv], 1), torch.cat([g, hg], 1)
        e2, v2, g2 = self.core.latent(e, v, g, receiver, sender)
        out = baseline + self.core.decode_nodes(v2, e, v, receiver) * scale
        return out, (torch.tanh(self.state_e(e2)), torch.tanh(self.state_v(v2)), torch.tanh(self.state_g(g2)))


class InferenceModel(nn.Module):
    """The recurrent inference model (section 8.2): a recurrent GN core reads the dynamic
    graphs of T observed frames, each concatenated with its hidden graph G_h, and returns
    G'(T), which the forward model takes concatenated with G_d. Trained jointly with it."""

    def __init__(self, cfg=None):
        super().__init__()
        self.cfg = cfg = dict(DEFAULTS, **(cfg or {}))
        S = cfg["state"]
        self.core = GNBlock(EDGE_FEATURES + S, NODE_FEATURES + S, GLOBAL_FEATURES + S, S, S, S, cfg)
        self.forward_model = ForwardModel(cfg, extra=(S, S, S))

    def observe(self, observed, receiver, sender):
        """observed: [(e, v, g)] of T frames -> G'(T) as (edge, node, global) features."""
        S = self.cfg["state"]
        e0, v0, _ = observed[0]
        h = (torch.zeros(e0.shape[0], S, device=e0.device), torch.zeros(v0.shape[0], S, device=e0.device),
             torch.zeros(1, S, device=e0.device))
        for e, v, g in observed:
            h = tuple(torch.tanh(x) for x in self.core(torch.cat([e, h[0]], 1), torch.cat([v, h[1]], 1),
                                                        torch.cat([g, h[2]], 1), receiver, sender))
        return h

    def forward(self, e, v, g, receiver, sender, baseline, scale, summary):
        he, hv, hg = summary
        return self.forward_model(torch.cat([e, he], 1), torch.cat([v, hv], 1), torch.cat([g, hg], 1), receiver,
                                  sender, baseline, scale)


KINDS = {"forward": ForwardModel, "recurrent": RecurrentForwardModel, "inference": InferenceModel}
