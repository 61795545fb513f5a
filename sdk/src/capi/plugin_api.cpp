// The single symbol a host needs after dlopen(): the whole API as a table.
#include "mbx/mbx.h"

namespace {

const mbx_api kApi = {
    sizeof(mbx_api),
    MBX_ABI_VERSION,
    mbx_version,
    mbx_status_name,
    mbx_context_create,
    mbx_context_destroy,
    mbx_context_last_error,
    mbx_context_last_error_info,
    mbx_context_set_progress,
    mbx_translate,
    mbx_mechanism_destroy,
    mbx_mechanism_release_host,
    mbx_mechanism_get_summary,
    mbx_mechanism_get_rigid_body,
    mbx_mechanism_find_part,
    mbx_mechanism_get_joint,
    mbx_mechanism_get_loop,
    mbx_mechanism_get_loop_joints,
    mbx_finding_code_name,
    mbx_mechanism_finding_count,
    mbx_mechanism_get_finding,
    mbx_mechanism_get_shape_stats,
    mbx_mechanism_write_report,
    mbx_abi_version,
    mbx_mechanism_export,
    mbx_mechatronics_create,
    mbx_mechatronics_destroy,
    mbx_mechatronics_load_library,
    mbx_mechatronics_load_library_text,
    mbx_mechatronics_load_drives,
    mbx_mechatronics_add_drive,
    mbx_mechatronics_set_motion,
    mbx_mechatronics_drive_count,
    mbx_mechanism_set_mechatronics,
    mbx_mechanism_drive_count,
    mbx_mechanism_get_drive,
    mbx_mechanism_drive_target,
    mbx_sim_model_create,
    mbx_sim_model_destroy,
    mbx_sim_model_get_info,
    mbx_sim_model_get_joint,
    mbx_sim_model_find_joint,
    mbx_sim_data_create,
    mbx_sim_data_destroy,
    mbx_sim_initialize,
    mbx_sim_get_state,
    mbx_sim_set_state,
    mbx_sim_get_joint_state,
    mbx_sim_set_joint_state,
    mbx_sim_set_effort,
    mbx_sim_set_drive_target,
    mbx_sim_step,
    mbx_sim_integrate,
    mbx_sim_inverse_dynamics,
    mbx_sim_forward_dynamics,
    mbx_sim_mass_matrix,
    mbx_sim_get_energy,
    mbx_sim_get_drive_signals,
    mbx_sim_get_stats,
    mbx_sim_run,
    mbx_mechatronics_set_joint_dynamics,
    mbx_calibrate,
    mbx_calibration_destroy,
    mbx_calibration_get_summary,
    mbx_calibration_get_cause,
    mbx_calibration_get_parameter,
    mbx_calibration_get_warning,
};

}  // namespace

extern "C" MBX_API const mbx_api* mbx_plugin_api(uint32_t host_abi_version) {
    // Tables only grow, so any host from ABI 1 on can use this one: an older
    // host reads its prefix, a newer one checks struct_size before using
    // functions this library does not have.
    return host_abi_version >= 1 ? &kApi : nullptr;
}
