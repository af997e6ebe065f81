#!/usr/bin/env bash
# The main job on the bundled sample: describe it, compress at 0.1 mm, decompress, verify.
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
build/capz info data/EB015PI.c3d
build/capz compress data/EB015PI.c3d --max-error 0.1mm -o "$out/EB015PI.capz"
build/capz decompress "$out/EB015PI.capz" -o "$out/EB015PI.back.c3d"
build/capz verify "$out/EB015PI.capz" --against data/EB015PI.c3d
