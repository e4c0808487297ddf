#!/bin/bash
# Zhou-Molinari-Ramesh's fragmenting bar on Akantu, for comparison with `cleave bench
# fragmentation` (see README.md here). Needs python3.11 and the package registry once:
#   python3.11 -m venv venv && ./venv/bin/pip install akantu numpy
# Rates 1, 3, 10 eps_dot0 x seeds 1, 2, 3; about 10 s a run on one core.
set -e
cd "$(dirname "$0")"
mkdir -p logs
for r in 1 3 10; do for s in 1 2 3; do
  ./venv/bin/python zmr1d.py --rate $r --seed $s > logs/r${r}_s${s}.txt 2>&1
done; done
./venv/bin/python summarize.py
