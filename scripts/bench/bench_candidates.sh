#!/usr/bin/env bash
# Usage: scripts/bench/bench_candidates.sh [--seeds 201,202,203,204,205] [--polyps 10] [--out DIR] [--images DIR]
# Polyp candidates over random-polyp phantoms (three variants per seed) and the shared CT:
# sensitivity per size class, false positives per volume, the FROC curve, the CT's candidates.
# The work is scripts/bench/bench_candidates.py's (its docstring says how each figure is made).
set -euo pipefail
cd "$(dirname "$0")/../.."
exec /usr/bin/python3 scripts/bench/bench_candidates.py "$@"
