#!/bin/sh
# The procedural texture unit (issue 15 §2) in the osu018 cell flow: ru_texture at Stages 4 with
# 1, 2 and 4 noise units inside (Octaves 8, the chip's configuration otherwise), each mapped as
# fast as ABC can (200 ps target) and for area (1000 ns). Resumable: a configuration whose
# .jsonl exists is skipped; each file is written by `rayunits synth --json` under a temporary
# name and renamed when the run succeeded. Usage: synth/texture/run.sh [RAYUNITS]
set -eu
RU=${1:-rayunits}
OUT=$(dirname "$0")/../results/texture
mkdir -p "$OUT"
for U in 1 2 4; do
  f="$OUT/texture_u${U}_s4.jsonl"
  [ -e "$f" ] && { echo "texture Units=$U: present ($f)"; continue; }
  echo "texture Units=$U: synthesizing ($(date +%T))"
  "$RU" synth texture --stages 4 --param Units=$U --flow osu018 --clock 200ps,1000000ps --timeout 3600 \
    --json "$f.tmp"
  mv "$f.tmp" "$f"
done
