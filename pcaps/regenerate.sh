#!/usr/bin/env bash
# Remakes the project's small demo captures with the simulator (deterministic per seed).
# usage: pcaps/regenerate.sh [path/to/vlpground]   (default: build/apps/vlpground)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
vlpground="${1:-${here}/../build/apps/vlpground}"
if [[ ! -x "${vlpground}" ]]; then
  echo "regenerate.sh: ${vlpground} not found; build it (cmake --build build --target vlpground_cli) or pass its path" >&2
  exit 2
fi
cd "${here}"
"${vlpground}" sim urban --seed 42 --frames 3 --mode strongest --out urban_demo
"${vlpground}" sim slope --seed 7 --frames 2 --mode dual --out slope_dual
"${vlpground}" sim hills --seed 3 --frames 2 --model hires --rpm 900 --out hills_demo
