#!/usr/bin/env bash
# Hostile inputs beside the fuzz targets (issue 28, docs/fuzzing.md): inputs
# that are well-formed but extreme, and files that are not files, generated
# afresh each run and given to the `mbx` CLI of the sanitizer build. Each
# class draws a few variants at random (the seed is printed; MBX_HOSTILE_SEED
# repeats a run). Every run must end within its time with either a result
# (exit 0, its files complete, no temporary left) or a message on stderr
# (exit 1 or 2, nothing written): never a sanitizer report, a signal, a hang
# or an exit 0 without its files.
#   fuzz/hostile_inputs.sh [build-dir] [variants per class]
set -uo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-asan}
per_class=${2:-4}
mbx="$build/bin/mbx"
[[ -x $mbx ]] || { echo "hostile_inputs: no $mbx (build the sanitizer build first)" >&2; exit 1; }
seed=${MBX_HOSTILE_SEED:-$(date +%s)}
RANDOM=$seed
echo "== hostile inputs: seed $seed, $per_class variants per class ($mbx)"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
arm=samples/emps_axis/emps_axis.xml
drives=samples/mechatronics/emps_axis_drives.xml
train=../shared/data/measured/emps/emps_train.csv
failures=0 runs=0

pick() { local a=("$@"); printf '%s' "${a[RANDOM % ${#a[@]}]}"; }

# Runs `mbx "$@"` into $out with a time limit and judges the outcome.
# `expect`: refuse (exit 1 or 2 with a message, nothing in $out), result (exit
# 0 with trajectory.csv or calibration.json), either.
check() {
  local expect=$1 limit=$2 out=$3
  shift 3
  runs=$((runs + 1))
  local status=0 started=$SECONDS
  timeout --kill-after=5 "$limit" "$mbx" "$@" >"$scratch/stdout" 2>"$scratch/stderr" || status=$?
  local why=""
  if grep -q -E 'AddressSanitizer|UndefinedBehaviorSanitizer|runtime error:|LeakSanitizer' "$scratch/stderr"; then
    why="a sanitizer report"
  elif ((status == 124 || status == 137)); then
    why="no end within ${limit} s"
  elif ((status >= 128)); then
    why="killed by signal $((status - 128))"
  elif ((status == 0)); then
    if [[ $expect == refuse ]]; then
      why="exit 0 where a refusal was due"
    elif ! [[ -s $out/trajectory.csv || -s $out/calibration.json || -s $out/report.json ]]; then
      why="exit 0 without its files"
    fi
  elif ((status == 1 || status == 2)); then
    if [[ $expect == result ]]; then
      why="a refusal where a result was due: $(head -c 300 "$scratch/stderr")"
    elif ! grep -q '^mbx' "$scratch/stderr"; then
      why="exit $status without a message"
    elif [[ -e $out/trajectory.csv || -e $out/calibration.json ]]; then
      why="exit $status with files written"
    fi
  else
    why="exit $status"
  fi
  if [[ -d $out ]] && compgen -G "$out/*.tmp.*" >/dev/null; then why="${why:+$why; }temporaries left in $out"; fi
  if [[ -n $why ]]; then
    failures=$((failures + 1))
    echo "FAIL ($why, $((SECONDS - started)) s): mbx $*" >&2
    tail -n 20 "$scratch/stderr" >&2
  fi
  rm -rf "$out"
}

experiment() {  # experiment <record> <path>: the EMPS columns on one record, fit and validation
  cat >"$2" <<EOF
<experiment version="1">
  <record file="$1" role="fit"/>
  <record file="$1" role="validation"/>
  <time column="t_s" unit="s"/>
  <column name="q_meas_m" joint="40:-:41" quantity="position" unit="m"/>
  <column name="force_N" joint="40:-:41" quantity="effort" unit="N"/>
  <drive mode="effort"/>
  <compare joint="40:-:41" quantity="position"/>
</experiment>
EOF
}

# 1. Files that are not regular files, or larger than the input limit.
mkfifo "$scratch/fifo"
mkdir -p "$scratch/folder"
truncate -s 3M "$scratch/sparse.xml"
for ((k = 0; k < per_class; k++)); do
  file=$(pick /dev/zero /dev/urandom "$scratch/fifo" "$scratch/folder" "$scratch/sparse.xml")
  case $(pick library drives experiment record) in
    library) args=(translate "$arm" --library "$file" -o "$scratch/out") ;;
    drives) args=(translate "$arm" --drives "$file" -o "$scratch/out") ;;
    experiment) args=(calibrate "$arm" --drives "$drives" --experiment "$file" -o "$scratch/out") ;;
    record)
      experiment "$file" "$scratch/experiment.xml"
      args=(calibrate "$arm" --drives "$drives" --experiment "$scratch/experiment.xml" -o "$scratch/out") ;;
  esac
  MBX_INPUT_LIMIT_MB=1 check refuse 60 "$scratch/out" "${args[@]}"
done

# 2. Extreme numbers in the simulation's options: every draw is either refused
# before the run or a short run.
for ((k = 0; k < per_class; k++)); do
  args=(simulate fourbar -o "$scratch/out" --stop-time "$(pick 1e17 1e308 -1 0 nan inf 1e-300 2 2junk)"
    --output-step "$(pick 1e9 0 -1 nan 1e-300 0.01 1e-15)" --step "$(pick 1e-12 0 nan 1e-3 -1e-3)"
    --gravity "$(pick 0,0,-9.81,1 0,0,-9.81junk 0,0 nan,0,0 1e308,0,0 0,0,-9.81)"
    --integrator "$(pick rk4 euler accurate)")
  check either 120 "$scratch/out" "${args[@]}"
done

# 3. Records with extreme or odd numbers: a value of 1e308, an infinity or
# NaN, a record too short, time that stands still; a byte-order mark and CRLF
# line ends are no fault.
for ((k = 0; k < per_class; k++)); do
  record="$scratch/record.csv"
  kind=$(pick huge nan short still bom crlf)
  case $kind in
    huge) awk -F, -v OFS=, 'NR == 2000 { $5 = "1e308" } { print }' "$train" | head -n 6000 >"$record" ;;
    nan) awk -F, -v OFS=, -v v="$(pick nan inf -inf 1e400)" 'NR == 3000 { $3 = v } { print }' "$train" | head -n 6000 >"$record" ;;
    short) head -n $((2 + RANDOM % 60)) "$train" >"$record" ;;
    still) awk -F, -v OFS=, 'NR == 2500 { $1 = "0.5" } { print }' "$train" | head -n 6000 >"$record" ;;
    bom) { printf '\xef\xbb\xbf'; head -n 6000 "$train"; } >"$record" ;;
    crlf) head -n 6000 "$train" | sed 's/$/\r/' >"$record" ;;
  esac
  experiment "$record" "$scratch/experiment.xml"
  expect=refuse
  [[ $kind == bom || $kind == crlf ]] && expect=result
  check "$expect" 300 "$scratch/out" calibrate "$arm" --drives "$drives" --experiment "$scratch/experiment.xml" -o "$scratch/out"
done

# 4. A run killed mid-write leaves its temporaries; the next run into the
# folder takes them away.
for ((k = 0; k < per_class && k < 2; k++)); do
  mkdir -p "$scratch/out"
  "$mbx" simulate fourbar --stop-time 1e5 --step 1e-3 --output-step 1e-3 -o "$scratch/out" >/dev/null 2>&1 &
  pid=$!
  sleep "$(pick 0.5 1 2)"
  kill -9 "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  if ! compgen -G "$scratch/out/*.tmp.*" >/dev/null; then
    echo "FAIL: the killed run left no temporary to clean (it should have been writing one)" >&2
    failures=$((failures + 1))
  fi
  check result 60 "$scratch/out" simulate fourbar --stop-time 0.1 -o "$scratch/out"
done

echo "== hostile inputs: $runs runs, $failures failed (seed $seed)"
((failures == 0))
