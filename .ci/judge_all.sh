#!/usr/bin/env bash
# Meshes every benchmark boundary with the release CLI and judges each result
# with the independent judge. Usage: .ci/judge_all.sh [OUTDIR] [extra mesh args...]
# Prints one line per case and a summary; exits non-zero if any case fails.
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
bench="$here/../shared/bench"
out=${1:-/tmp/quadex_judge}; shift || true
mkdir -p "$out"
bin="$here/target/release/quadex"
pass=0; fail=0
for f in "$bench"/boundaries/*.poly "$bench"/peer/*.poly "$bench"/edge/*.poly; do
  name=$(basename "$f" .poly)
  case "$name" in disk1600|disk6400) [ -n "${QUADEX_LARGE:-}" ] || continue ;; esac
  msh="$out/$name.msh"
  rm -f "$msh"
  if ! timeout ${QUADEX_CASE_TIMEOUT:-120} "$bin" mesh "$f" -o "$msh" --report "$out/$name.json" "$@" > "$out/$name.log" 2>&1; then
    echo "FAIL $name: $(tail -1 "$out/$name.log")"; fail=$((fail+1)); continue
  fi
  j=$(python3 "$bench/tools/judge.py" "$f" "$msh")
  if echo "$j" | grep -q '"valid": true'; then
    pass=$((pass+1)); echo "ok   $name $(echo $j)"
  else
    fail=$((fail+1)); echo "FAIL $name $(echo $j)"
  fi
done
echo "judged: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
