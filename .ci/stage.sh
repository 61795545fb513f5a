# Sourced by the CI scripts: `stage NAME command...` runs the command and says
# how many minutes it took (also appended to $MBX_CI_TIMES when set), so every
# CI log shows where its time went.
stage() {
  local name=$1 start end status=0
  shift
  start=$(date +%s)
  "$@" || status=$?
  end=$(date +%s)
  local line
  line=$(awk -v n="$name" -v s=$((end - start)) 'BEGIN { printf "%-16s %6.1f min", n, s / 60 }')
  echo "== stage: $line$( ((status)) && echo " (failed: $status)")"
  [[ -n "${MBX_CI_TIMES:-}" ]] && echo "$line" >>"$MBX_CI_TIMES"
  return "$status"
}
