#!/bin/bash
# Error per second of `vkgi reference` against Mitsuba 3 on this machine's CPU (issue: the
# reference path tracer against its peer). Not part of CI or `cargo bench`: it downloads
# Mitsuba from PyPI into target/mitsuba-venv on first use. Arguments go to compare.py, e.g.
#   bash benches/mitsuba/run.sh --spp 256 --runs 3 --converged-spp 4096
# Results: docs/performance.md ("The reference path tracer against Mitsuba 3").
set -euo pipefail
cd "$(dirname "$0")/../.."
source .ci/env
venv=target/mitsuba-venv
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet mitsuba==3.9.1
fi
cargo build --release --quiet
exec "$venv/bin/python" benches/mitsuba/compare.py --vkgi target/release/vkgi \
  --work target/mitsuba-work "$@"
