#!/usr/bin/env bash
# The suite's rules that a compiler cannot enforce (docs/testing.md):
# - real numbers are compared with relative() or within() (tests/common/near.h),
#   never doctest's Approx, whose epsilon turns absolute below 1;
# - a test that cannot run skips with MBX_SKIP (tests/common/skip.h), never by a
#   doctest::skip decorator (ctest never sees those cases) or a silent return
#   after a message.
set -uo pipefail
root=${1:-$(dirname "$0")}
files=$(find "$root" \( -name '*.cpp' -o -name '*.h' \) -not -path '*/common/near.h' -not -path '*/common/skip.h')
status=0
refuse() {
  local pattern=$1 why=$2 hits
  # shellcheck disable=SC2086
  hits=$(grep -nE "$pattern" $files)
  if [[ -n "$hits" ]]; then
    echo "$why:"
    echo "$hits"
    status=1
  fi
}
refuse '(^|[^A-Za-z_])Approx[[:space:]]*\(|doctest::Approx' \
  "doctest's Approx (use relative() or within() from tests/common/near.h)"
refuse '\.epsilon[[:space:]]*\(' "an epsilon (use relative() or within() from tests/common/near.h)"
refuse 'doctest::skip' "a doctest::skip decorator (call MBX_SKIP with the reason)"
refuse 'MESSAGE\(.*[Ss]kip' "a skip told only in a message (call MBX_SKIP or MBX_SKIP_PART with the reason)"
# ctest's test list splits a name at ';': the halves match no case and pass having run nothing.
refuse 'TEST_CASE\("[^"]*;' "a ';' in a test case's name (ctest splits it there)"
if ((status == 0)); then
  echo "test rules hold over $(echo "$files" | wc -l) files"
fi
exit $status
