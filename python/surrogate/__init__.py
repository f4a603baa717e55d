"""Learned surrogates of peridynamic fracture on peri's graph datasets (docs/surrogates.md):
the scenario generator (generate), the graph loader (graphs), the graph-network models of
Ebrahimi 2020 chapter 8 (models), training (train) and rollout evaluation (evaluate)."""
