/* See c_enum_call.c. */
#pragma once
#include <mbx/mbx.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef mbx_status (*mbx_set_motion_fn)(mbx_context *, mbx_mechatronics *, const char *, int32_t,
                                        const mbx_motion_point *, uint32_t, mbx_interpolation);

/* set_motion(..., (mbx_interpolation)interpolation), the cast done in C. */
mbx_status mbx_test_set_motion_with_raw_interpolation(mbx_set_motion_fn set_motion, mbx_context *ctx,
                                                      mbx_mechatronics *mechatronics, const char *joint_id,
                                                      int32_t drive_index, const mbx_motion_point *points,
                                                      uint32_t count, int interpolation);

#ifdef __cplusplus
}
#endif
