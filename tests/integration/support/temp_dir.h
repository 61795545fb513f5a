// The shared test TempDir under this suite's namespace.
#pragma once

#include "../../common/temp_dir.h"

namespace itest {
using mbx_test::TempDir;
}  // namespace itest
