/*
 * mbx.h must be usable from strict C99 (built with -std=c99 -Wall -Wextra
 * -pedantic -Werror): this file includes it, touches its types and macros,
 * and loads the plugin the way a C host would.
 * Usage: mbx_c99_api_check <path to libmbx.so>. Exit 0 on success.
 */
#define _POSIX_C_SOURCE 200809L

#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

#include <mbx/mbx.h>

/* Compile-time checks, C99 style (no _Static_assert). */
typedef char check_host_v1_smaller[(MBX_HOST_V1_SIZE < sizeof(mbx_host)) ? 1 : -1];
typedef char check_struct_size_first[(offsetof(mbx_body_desc, struct_size) == 0) ? 1 : -1];
typedef char check_abi_version[(MBX_ABI_VERSION >= 2u) ? 1 : -1];
/* ABI 5: the mechatronics structs keep struct_size first; overrides and
 * motion points are fixed-layout array elements without one. */
typedef char check_abi_5[(MBX_ABI_VERSION >= 5u) ? 1 : -1];
typedef char check_drive_desc_first[(offsetof(mbx_drive_desc, struct_size) == 0) ? 1 : -1];
typedef char check_controller_first[(offsetof(mbx_controller_desc, struct_size) == 0) ? 1 : -1];
typedef char check_drive_info_first[(offsetof(mbx_drive_info, struct_size) == 0) ? 1 : -1];
typedef char check_motion_point[(sizeof(mbx_motion_point) == 2 * sizeof(double)) ? 1 : -1];
typedef char check_api_grows[(offsetof(mbx_api, mechanism_drive_target) > offsetof(mbx_api, mechanism_export)) ? 1 : -1];

/* ABI 6: the simulation structs keep struct_size first; fixed values are
 * fixed-layout array elements without one. */
typedef char check_abi_6[(MBX_ABI_VERSION >= 6u) ? 1 : -1];
typedef char check_sim_options_first[(offsetof(mbx_sim_options, struct_size) == 0) ? 1 : -1];
typedef char check_sim_joint_first[(offsetof(mbx_sim_joint_info, struct_size) == 0) ? 1 : -1];
typedef char check_joint_dynamics_first[(offsetof(mbx_joint_dynamics_desc, struct_size) == 0) ? 1 : -1];
typedef char check_fixed_value_layout[(offsetof(mbx_sim_fixed_value, value) == 3 * sizeof(uint32_t) + 4) ? 1 : -1];
typedef char check_api_grows_6[(offsetof(mbx_api, sim_run) > offsetof(mbx_api, mechanism_drive_target)) ? 1 : -1];

/* ABI 7: mbx_joint_dynamics_desc grew at its end (offset ... asymmetric);
 * an ABI 6 caller's struct ends before offset. */
typedef char check_abi_7[(MBX_ABI_VERSION >= 7u) ? 1 : -1];
typedef char check_joint_dynamics_grows[(offsetof(mbx_joint_dynamics_desc, offset) >=
                                         offsetof(mbx_joint_dynamics_desc, upper) + sizeof(double)) ? 1 : -1];
typedef char check_joint_dynamics_last[(offsetof(mbx_joint_dynamics_desc, asymmetric) >
                                        offsetof(mbx_joint_dynamics_desc, stribeck_velocity)) ? 1 : -1];

/* ABI 9: the contact structs keep struct_size first; their entries follow
 * the calibration ones in the table. */
typedef char check_abi_9[(MBX_ABI_VERSION >= 9u) ? 1 : -1];
typedef char check_collision_shape_first[(offsetof(mbx_collision_shape_desc, struct_size) == 0) ? 1 : -1];
typedef char check_contact_material_first[(offsetof(mbx_contact_material_desc, struct_size) == 0) ? 1 : -1];
typedef char check_api_grows_9[(offsetof(mbx_api, mechanism_collision_shape_count) >
                                offsetof(mbx_api, calibration_get_warning)) ? 1 : -1];

/* A one-motor library, as a C host might hold it in memory. */
static const char *const k_library =
    "<object_library version=\"1\"><object_folder name=\"Motors\">"
    "<object_class name=\"DC\" kind=\"dc_motor\" modelica=\"M.DC\">"
    "<parameter name=\"J_Rotor\" unit=\"kg.m2\"/><parameter name=\"VaNominal\" unit=\"V\"/>"
    "<parameter name=\"IaNominal\" unit=\"A\"/><parameter name=\"rpmNominal\" unit=\"rpm\"/>"
    "<parameter name=\"Ra\" unit=\"Ohm\"/>"
    "<object name=\"m\" ID=\"0123456789abcdef0123456789ABCDEF\">"
    "<parameter name=\"J_Rotor\" value=\"1e-6\"/><parameter name=\"VaNominal\" value=\"12\"/>"
    "<parameter name=\"IaNominal\" value=\"1\"/><parameter name=\"rpmNominal\" value=\"3000\"/>"
    "<parameter name=\"Ra\" value=\"2\"/></object></object_class></object_folder></object_library>";

/* The mechatronics entry points from C: form checks that need no mechanism.
 * Returns 0 when everything behaved. */
static int check_mechatronics(const mbx_api *api, mbx_context *context) {
    mbx_mechatronics *mechatronics = NULL;
    mbx_controller_desc controller = {0};
    mbx_drive_desc drive = {0};
    mbx_drive_info info = {0};
    mbx_parameter_override overrides[1] = {{"Ratio", 2.0}};
    mbx_motion_point points[2] = {{0.0, 0.0}, {1.0, 0.5}};
    mbx_status (*target)(const mbx_mechanism *, uint32_t, double, double *) = api->mechanism_drive_target;
    mbx_status (*get_drive)(const mbx_mechanism *, uint32_t, mbx_drive_info *) = api->mechanism_get_drive;
    mbx_status (*attach)(mbx_context *, mbx_mechanism *, const mbx_mechatronics *) = api->mechanism_set_mechatronics;
    uint32_t (*count)(const mbx_mechanism *) = api->mechanism_drive_count;
    double q[3] = {0.0, 0.0, 0.0};
    int failures = 0;

    if (api->abi_version < 5u || api->struct_size < offsetof(mbx_api, mechanism_drive_target) + sizeof target) {
        fprintf(stderr, "the API table has no ABI 5 entries\n");
        return 1;
    }
    if (!target || !get_drive || !attach || !count || !api->mechatronics_load_drives) {
        fprintf(stderr, "NULL ABI 5 entries\n");
        return 1;
    }
    if (api->mechatronics_create(context, &mechatronics) != MBX_OK || !mechatronics) {
        fprintf(stderr, "mechatronics_create failed\n");
        return 1;
    }
    if (api->mechatronics_load_library_text(context, mechatronics, k_library, "c99.xml") != MBX_OK) {
        fprintf(stderr, "load_library_text: %s\n", api->context_last_error(context));
        ++failures;
    }
    controller.struct_size = sizeof controller;
    controller.kp = 10.0;
    controller.velocity_estimate = MBX_VELOCITY_MEASURED;
    drive.struct_size = sizeof drive;
    drive.constraint_id = "J";
    drive.primitive_index = -1;
    drive.motor_id = "0123456789ABCDEF0123456789ABCDEF";
    drive.amplifier_mode = MBX_AMPLIFIER_VOLTAGE;
    drive.controller = &controller;
    drive.overrides = overrides;
    drive.override_count = 1;
    if (api->mechatronics_add_drive(context, mechatronics, &drive) != MBX_OK ||
        api->mechatronics_drive_count(mechatronics) != 1) {
        fprintf(stderr, "add_drive: %s\n", api->context_last_error(context));
        ++failures;
    }
    if (api->mechatronics_set_motion(context, mechatronics, "J", -1, points, 2, MBX_INTERPOLATION_SMOOTH) != MBX_OK) {
        fprintf(stderr, "set_motion: %s\n", api->context_last_error(context));
        ++failures;
    }
    /* Values outside the enums, as C allows: refused, not undefined. */
    if (api->mechatronics_set_motion(context, mechatronics, "J", -1, points, 2, (mbx_interpolation)9) !=
        MBX_ERROR_INVALID_ARGUMENT) {
        fprintf(stderr, "interpolation 9 was not refused\n");
        ++failures;
    }
    drive.amplifier_mode = (mbx_amplifier_mode)7;
    if (api->mechatronics_add_drive(context, mechatronics, &drive) == MBX_OK) {
        fprintf(stderr, "amplifier_mode 7 was accepted\n");
        ++failures;
    }
    drive.amplifier_mode = MBX_AMPLIFIER_VOLTAGE;
    drive.controller = NULL;
    if (api->mechatronics_add_drive(context, mechatronics, &drive) == MBX_OK) {
        fprintf(stderr, "a drive without a controller was accepted\n");
        ++failures;
    }
    if (api->mechatronics_drive_count(mechatronics) != 1) {
        fprintf(stderr, "a refused drive changed the drive count\n");
        ++failures;
    }
    info.struct_size = sizeof info;
    if (count(NULL) != 0 || get_drive(NULL, 0, &info) != MBX_ERROR_INVALID_ARGUMENT ||
        target(NULL, 0, 0.0, q) != MBX_ERROR_INVALID_ARGUMENT ||
        attach(context, NULL, mechatronics) != MBX_ERROR_INVALID_ARGUMENT) {
        fprintf(stderr, "NULL mechanisms were not refused\n");
        ++failures;
    }
    api->mechatronics_destroy(mechatronics);
    return failures;
}

/* The simulation entry points from C: refusals that need no mechanism. */
static int check_simulation(const mbx_api *api, mbx_context *context) {
    mbx_sim_model *model = NULL;
    mbx_sim_data *data = NULL;
    mbx_sim_options options;
    mbx_sim_stats stats;
    mbx_joint_dynamics_desc dynamics;
    mbx_mechatronics *mechatronics = NULL;
    int failures = 0;

    if (api->abi_version < 6u || api->struct_size < offsetof(mbx_api, mechatronics_set_joint_dynamics) + sizeof(void *)) {
        fprintf(stderr, "the API table has no ABI 6 entries\n");
        return 1;
    }
    memset(&options, 0, sizeof options);
    options.struct_size = sizeof options;
    options.integrator = MBX_INTEGRATOR_ACCURATE;
    if (api->sim_model_create(context, NULL, &options, &model) != MBX_ERROR_INVALID_ARGUMENT || model) {
        fprintf(stderr, "a NULL mechanism was not refused\n");
        ++failures;
    }
    if (api->sim_data_create(context, NULL, &data) != MBX_ERROR_INVALID_ARGUMENT || data) {
        fprintf(stderr, "a NULL model was not refused\n");
        ++failures;
    }
    memset(&stats, 0, sizeof stats);
    stats.struct_size = sizeof stats;
    if (api->sim_get_stats(NULL, &stats) != MBX_ERROR_INVALID_ARGUMENT ||
        api->sim_step(context, NULL, 1) != MBX_ERROR_INVALID_ARGUMENT) {
        fprintf(stderr, "NULL data was not refused\n");
        ++failures;
    }
    if (strcmp(api->status_name(MBX_ERROR_SIMULATION), "MBX_ERROR_SIMULATION") != 0) {
        fprintf(stderr, "MBX_ERROR_SIMULATION has no name\n");
        ++failures;
    }
    if (api->mechatronics_create(context, &mechatronics) != MBX_OK) return failures + 1;
    memset(&dynamics, 0, sizeof dynamics);
    dynamics.struct_size = sizeof dynamics;
    dynamics.constraint_id = "J";
    dynamics.primitive_index = -1;
    dynamics.damping = 0.5;
    dynamics.limited = 1;
    dynamics.lower = 1.0;
    dynamics.upper = -1.0;
    if (api->mechatronics_set_joint_dynamics(context, mechatronics, &dynamics) != MBX_ERROR_INVALID_INPUT) {
        fprintf(stderr, "limits with lower > upper were accepted\n");
        ++failures;
    }
    dynamics.upper = 2.0;
    if (api->mechatronics_set_joint_dynamics(context, mechatronics, &dynamics) != MBX_OK) {
        fprintf(stderr, "set_joint_dynamics: %s\n", api->context_last_error(context));
        ++failures;
    }
    /* ABI 7 fields: a Stribeck peak needs its decay speed. */
    dynamics.offset = -3.16;
    dynamics.asymmetric = 1;
    dynamics.coulomb_negative = 0.5;
    dynamics.stribeck = 0.2;
    if (api->mechatronics_set_joint_dynamics(context, mechatronics, &dynamics) != MBX_ERROR_INVALID_INPUT) {
        fprintf(stderr, "a Stribeck peak without stribeck_velocity was accepted\n");
        ++failures;
    }
    dynamics.stribeck_velocity = 0.01;
    if (api->mechatronics_set_joint_dynamics(context, mechatronics, &dynamics) != MBX_OK) {
        fprintf(stderr, "set_joint_dynamics (ABI 7 fields): %s\n", api->context_last_error(context));
        ++failures;
    }
    api->mechatronics_destroy(mechatronics);
    return failures;
}

static int count_bodies(void *user_data, size_t *out_count) {
    (void)user_data;
    *out_count = 0;
    return 0;
}

int main(int argc, char **argv) {
    void *library;
    void *symbol;
    mbx_plugin_api_fn entry;
    const mbx_api *api;
    const char *version;
    mbx_host host;
    mbx_body_desc body;
    mbx_units units = {1e-3, 1e-3, 0.0};
    mbx_context *context = NULL;
    size_t count = 1;

    if (argc != 2) {
        fprintf(stderr, "usage: %s <libmbx.so>\n", argv[0]);
        return 2;
    }
    library = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        fprintf(stderr, "dlopen: %s\n", dlerror());
        return 1;
    }
    symbol = dlsym(library, MBX_PLUGIN_ENTRY_NAME);
    if (!symbol) {
        fprintf(stderr, "no %s\n", MBX_PLUGIN_ENTRY_NAME);
        return 1;
    }
    /* ISO C has no object-to-function pointer conversion; copy the bits. */
    memcpy(&entry, &symbol, sizeof entry);
    api = entry(MBX_ABI_VERSION);
    if (!api || api->struct_size < offsetof(mbx_api, abi_version_fn)) {
        fprintf(stderr, "no usable API table\n");
        return 1;
    }
    version = api->version();
    if (!version || !*version) {
        fprintf(stderr, "empty mbx_version\n");
        return 1;
    }

    memset(&body, 0, sizeof body);
    body.struct_size = (uint32_t)offsetof(mbx_body_desc, mass);
    body.units = units;
    if (MBX_FIELD_FITS(&body, mbx_body_desc, mass) || !MBX_FIELD_FITS(&body, mbx_body_desc, units)) {
        fprintf(stderr, "MBX_FIELD_FITS is wrong\n");
        return 1;
    }

    memset(&host, 0, sizeof host);
    host.struct_size = sizeof host;
    host.abi_version = MBX_HOST_ABI_VERSION;
    host.body_count = count_bodies;
    if (!MBX_FIELD_FITS(&host, mbx_host, describe_assembly) || host.body_count(NULL, &count) != 0 || count != 0) {
        fprintf(stderr, "host table checks failed\n");
        return 1;
    }
    if (api->context_create(&context) != MBX_OK || !context) {
        fprintf(stderr, "context_create failed\n");
        return 1;
    }
    if (api->translate(context, NULL, NULL, NULL) != MBX_ERROR_INVALID_ARGUMENT) {
        fprintf(stderr, "NULL arguments were not refused\n");
        api->context_destroy(context);
        return 1;
    }
    if (check_mechatronics(api, context) != 0 || check_simulation(api, context) != 0) {
        api->context_destroy(context);
        return 1;
    }
    api->context_destroy(context);
    printf("mbx %s (%s) from C99\n", version, api->status_name(MBX_OK));
    dlclose(library);
    return 0;
}
