/* Calls made from C, where an enum parameter may carry any int: C++ cannot
 * hold a value outside an enum's range without undefined behaviour of its own
 * (clang's UBSan refuses both the value and a call through a cast function
 * pointer), while a C host passes such values freely. */
#include <mbx/mbx.h>

#include "c_enum_call.h"

mbx_status mbx_test_set_motion_with_raw_interpolation(mbx_set_motion_fn set_motion, mbx_context *ctx,
                                                      mbx_mechatronics *mechatronics, const char *joint_id,
                                                      int32_t drive_index, const mbx_motion_point *points,
                                                      uint32_t count, int interpolation) {
    return set_motion(ctx, mechatronics, joint_id, drive_index, points, count, (mbx_interpolation)interpolation);
}
