#!/usr/bin/env bash
# Learned surrogate end to end (docs/surrogates.md): a small graph dataset of 2D plates in
# tension from the shipped material table (8 train and 2 test materials, no defect, a
# pre-crack and random holes, two loads: 60 runs of a coarse plate, about a minute), a few
# minutes of training of the forward model on the CPU (or CUDA when present), then the
# one-step and 10-step errors on the test materials beside the constant-velocity baseline
# and, for each test run, a damage map with PD above and the surrogate below at rollout
# steps 1, 5, 10 (output/surrogate/pictures/*.png).
#
# Full size (the seed's 50 train / 10 test materials, a 1 mm plate, section 8.3 sizes; hours
# on a CPU, use a GPU):
#   TRAIN=50 TEST=10 SPACING=1e-3 MINUTES=120 SIZES="" bash examples/surrogate/run.sh
# Usage: bash examples/surrogate/run.sh   (from the repository root, after make build)
set -euo pipefail
OUT=${OUT:-output/surrogate}
PERI=${PERI:-build/peri}
PYTHON=${PYTHON:-/usr/bin/python3}
SIZES=${SIZES:---edge-hidden 32 --node-hidden 32 --global-hidden 32 --latent 16 --state 8}
export PYTHONPATH="$(pwd)/python${PYTHONPATH:+:$PYTHONPATH}"
"$PYTHON" -m surrogate.generate --out "$OUT/data" --train "${TRAIN:-8}" --test "${TEST:-2}" \
  --spacing "${SPACING:-2e-3}" --steps 100 --every 5 --loads 0.6,1.0 --seed 1 --peri "$PERI"
"$PYTHON" -m surrogate.train --data "$OUT/data" --model forward --out "$OUT/forward.pt" \
  --minutes "${MINUTES:-4}" --lr 3e-3 --batch 2 --noise 0.05 $SIZES
"$PYTHON" -m surrogate.evaluate --data "$OUT/data" --checkpoint "$OUT/forward.pt" --steps 10 \
  --pictures "$OUT/pictures" --at 1,5,10 | tee "$OUT/errors.json"
