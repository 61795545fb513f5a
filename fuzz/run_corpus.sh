#!/usr/bin/env bash
# Builds the libFuzzer targets in the sanitizer build (build-asan/: clang-15,
# ASan+UBSan and coverage, .ci/configure; the sanitizer suite's build, so after
# `.ci/test --sanitize` only the fuzz executables are linked) and runs each on
# the committed corpus for a short while: what CI does. The
# corpus in fuzz/corpus/ is only read; new inputs go to a scratch folder. The
# targets run side by side, one per core.
#   fuzz/run_corpus.sh                 every target, 30 s each
#   fuzz/run_corpus.sh 600 vrml csv    chosen targets, 10 min each
# A crash, leak, timeout or out-of-memory stops with the input saved under
# $MBX_FUZZ_OUT (default build-fuzz/artifacts/); make it a regression test
# (docs/fuzzing.md).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(pmxml vrml object_library drive_file experiment csv host_table step step_mesh simscape urdf)
bash .ci/install-deps  # clang-15, libfuzzer-15-dev, libomp-15-dev among them
dir=$(bash .ci/configure sanitize)
out=${MBX_FUZZ_OUT:-$dir/artifacts}
cmake --build "$dir" -j "$(nproc)" --target $(printf 'fuzz_%s ' "${targets[@]}")

mkdir -p "$out"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
# One target on its corpus; its log and exit status go to the scratch folder.
run_target() {
  local t=$1 dict=() status=0
  case $t in
    vrml) dict=(-dict=fuzz/dict/vrml.dict) ;;
    pmxml | object_library | drive_file | experiment | simscape | urdf) dict=(-dict=fuzz/dict/xml.dict) ;;
    step | step_mesh) dict=(-dict=fuzz/dict/step.dict) ;;
  esac
  # The STEP reader also starts from real parts (../shared, read only).
  local seeds=()
  if [[ $t == step || $t == step_mesh ]]; then
    mkdir -p "$scratch/${t}_seeds"
    for f in ../shared/data/step/dfki_double_pendulum/lever_*.STEP /usr/share/opencascade/data/step/screw.step; do
      [[ -f $f ]] && ln -sf "$(realpath "$f")" "$scratch/${t}_seeds/"
    done
    seeds=("$scratch/${t}_seeds")
  fi
  mkdir -p "$scratch/$t"
  # -timeout: one input taking 10 s is a hang; -rss_limit_mb: libFuzzer's
  # default, stated so the figures in docs/fuzzing.md say what they were run with.
  "$dir/bin/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$out/fuzz_${t}-" "${dict[@]}" "$scratch/$t" "fuzz/corpus/$t" "${seeds[@]}" >"$scratch/$t.log" 2>&1 || status=$?
  echo "$status" >"$scratch/$t.status"
}
# Each target is one single-threaded process: as many run at once as there are
# cores, each for the whole of its seconds.
for t in "${targets[@]}"; do
  while (($(jobs -rp | wc -l) >= $(nproc))); do wait -n || true; done
  run_target "$t" &
done
wait
failed=0
for t in "${targets[@]}"; do
  echo "== fuzz_$t: ${seconds} s"
  grep -E '^#[0-9]+[[:space:]]+(INITED|DONE)|^stat::(number_of_executed_units|peak_rss_mb)|^Done ' "$scratch/$t.log" || true
  status=$(cat "$scratch/$t.status" 2>/dev/null || echo 1)
  if ((status)); then
    tail -n 80 "$scratch/$t.log" >&2
    echo "fuzz_$t failed (status $status); the input is in $out" >&2
    failed=1
  fi
done
exit $failed
