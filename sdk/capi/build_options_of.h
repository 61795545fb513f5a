// The simulation model's build options of a mechanism handle, as every user
// of its dynamics needs them (mbx_sim_model_create, mbx_calibrate,
// mbx_excite): gravity (the options' when MBX_SIM_SET_GRAVITY is set, else
// the default), turned by the attached description's <mounting>, and its
// drives, joint dynamics and transmissions.
#pragma once
#include <cmath>

#include "sdk/capi/guard.h"
#include "sdk/capi/handles.h"
#include "sim/build_model.h"
#include "sim/resolved_joint_dynamics.h"

inline mbx::sim::BuildOptions build_options_of(const mbx_mechanism& mechanism, uint32_t flags, const double gravity[3]) {
    mbx::sim::BuildOptions build;
    if (flags & MBX_SIM_SET_GRAVITY) {
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(gravity[k])) mbx::bad_argument("gravity is not finite");
        build.gravity = mbx::Vec3(gravity[0], gravity[1], gravity[2]);
    }
    build.gravity = mbx::tilted_gravity(build.gravity, mechanism.mounting);
    build.drives = mechanism.drives;
    build.joint_dynamics = mbx::sim::joint_dynamics_by_joint(mechanism.joint_dynamics);
    build.transmissions = mbx::sim::transmissions_by_joint(mechanism.joint_dynamics);
    return build;
}
