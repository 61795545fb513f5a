/*
 * A C host built against the installed SDK (find_package(mbx) or
 * pkg-config): translates the five-axis arm sample through libmbx_files and
 * writes its report, then swings its own pendulum (pendulum_host.h) for half
 * a period and compares with the closed form.
 * Usage: c_host <samples dir> <output dir>. Exit 0 when every check holds.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <mbx/mbx.h>
#include <mbx/mbx_files.h>

#include "pendulum_host.h"

static int failures = 0;
#define CHECK(cond)                                                                  \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
            ++failures;                                                              \
        }                                                                            \
    } while (0)
#define REQUIRE_OK(ctx, call)                                                                          \
    do {                                                                                               \
        mbx_status s_ = (call);                                                                        \
        if (s_ != MBX_OK) {                                                                            \
            fprintf(stderr, "%s:%d: %s: %s: %s\n", __FILE__, __LINE__, #call, mbx_status_name(s_),    \
                    (ctx) ? mbx_context_last_error(ctx) : "");                                         \
            return 1;                                                                                  \
        }                                                                                              \
    } while (0)

static int translate_arm(mbx_context *ctx, const char *samples, const char *out) {
    char xml[4096], wrl[4096], report[4096];
    snprintf(xml, sizeof xml, "%s/five_axis_arm/five_axis_arm.xml", samples);
    snprintf(wrl, sizeof wrl, "%s/five_axis_arm/five_axis_arm_a.wrl", samples);
    mbx_files_options fo;
    memset(&fo, 0, sizeof fo);
    fo.struct_size = sizeof fo;
    fo.shapes = wrl;
    mbx_files_error fe;
    memset(&fe, 0, sizeof fe);
    fe.struct_size = sizeof fe;
    mbx_file_host *files = NULL;
    if (mbx_files_open(xml, &fo, &files, &fe) != 0) {
        fprintf(stderr, "%s:%d: %s\n", fe.file, fe.line, fe.message);
        return 1;
    }
    mbx_mechanism *m = NULL;
    REQUIRE_OK(ctx, mbx_translate(ctx, mbx_files_host(files), NULL, &m));
    mbx_mechanism_summary s;
    memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    REQUIRE_OK(ctx, mbx_mechanism_get_summary(m, &s));
    /* samples/five_axis_arm/README.md, "Expected mechanism". */
    CHECK(s.part_count == 8);
    CHECK(s.weld_count == 2);
    CHECK(s.rigid_body_count == 5);
    CHECK(s.revolute_count == 5);
    CHECK(s.joint_count == 5);
    CHECK(s.loop_count == 0);
    CHECK(s.dof == 5);
    CHECK(s.error_count == 0);
    snprintf(report, sizeof report, "%s/c_host_arm", out);
    REQUIRE_OK(ctx, mbx_mechanism_write_report(ctx, m, report));
    snprintf(report, sizeof report, "%s/c_host_arm/report.json", out);
    FILE *f = fopen(report, "r");
    CHECK(f != NULL);
    if (f) fclose(f);
    mbx_mechanism_destroy(m);
    mbx_files_close(files);

    /* Bad arguments are errors with a message, not crashes. */
    CHECK(mbx_files_open(NULL, NULL, &files, &fe) != 0 && files == NULL && strlen(fe.message) > 0);
    CHECK(mbx_files_open(xml, NULL, NULL, &fe) != 0 && strstr(fe.message, "out") != NULL);
    mbx_files_options small = fo;
    small.struct_size = 4;
    CHECK(mbx_files_open(xml, &small, &files, &fe) != 0 && strstr(fe.message, "struct_size") != NULL);
    CHECK(mbx_files_host(NULL) == NULL);
    mbx_files_close(NULL);

    /* A missing file is an error naming it, not a crash. */
    snprintf(xml, sizeof xml, "%s/no_such_file.xml", samples);
    CHECK(mbx_files_open(xml, NULL, &files, &fe) != 0);
    CHECK(files == NULL);
    CHECK(strstr(fe.file, "no_such_file.xml") != NULL);
    return 0;
}

static int swing_pendulum(mbx_context *ctx) {
    const mbx_host host = pendulum_host();
    mbx_mechanism *m = NULL;
    REQUIRE_OK(ctx, mbx_translate(ctx, &host, NULL, &m));
    mbx_sim_options so;
    memset(&so, 0, sizeof so);
    so.struct_size = sizeof so;
    so.integrator = MBX_INTEGRATOR_RK4;
    so.step = 1e-3;
    mbx_sim_model *model = NULL;
    REQUIRE_OK(ctx, mbx_sim_model_create(ctx, m, &so, &model));
    mbx_sim_model_info info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    REQUIRE_OK(ctx, mbx_sim_model_get_info(model, &info));
    CHECK(info.nq == 1 && info.nv == 1);
    mbx_sim_data *data = NULL;
    REQUIRE_OK(ctx, mbx_sim_data_create(ctx, model, &data));

    /* Small swing: q(t) = q0 cos(omega t); at half a period q = -q0. The
     * amplitude's own period lengthening (q0^2 / 16) is 6e-8 here. */
    const double inertia = PENDULUM_M * PENDULUM_L * PENDULUM_L + PENDULUM_IC;
    const double omega = sqrt(PENDULUM_M * PENDULUM_G * PENDULUM_L / inertia);
    const double q0 = 1e-3, half_period = 3.14159265358979323846 / omega;
    mbx_sim_fixed_value start;
    memset(&start, 0, sizeof start);
    start.value = q0;
    REQUIRE_OK(ctx, mbx_sim_initialize(ctx, data, &start, 1));
    double mass_matrix = 0;
    REQUIRE_OK(ctx, mbx_sim_mass_matrix(ctx, data, &mass_matrix));
    CHECK(fabs(mass_matrix - inertia) < 1e-12);

    double t = 0, q = 0, v = 0;
    REQUIRE_OK(ctx, mbx_sim_integrate(ctx, data, half_period / 2));
    REQUIRE_OK(ctx, mbx_sim_get_state(data, &t, &q, &v));
    CHECK(fabs(q) < 1e-4 * q0);
    CHECK(fabs(v + q0 * omega) < 1e-4 * q0 * omega);
    REQUIRE_OK(ctx, mbx_sim_integrate(ctx, data, half_period));
    REQUIRE_OK(ctx, mbx_sim_get_state(data, &t, &q, &v));
    CHECK(fabs(t - half_period) < 1e-12);
    CHECK(fabs(q + q0) < 1e-4 * q0);
    printf("c_host: pendulum q(T/2) = %.9g (closed form %.9g), I = %.6g\n", q, -q0, mass_matrix);

    mbx_sim_data_destroy(data);
    mbx_sim_model_destroy(model);
    mbx_mechanism_destroy(m);
    return 0;
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: c_host <samples dir> <output dir>\n");
        return 2;
    }
    CHECK(strcmp(mbx_version(), MBX_VERSION_STRING) == 0);
    CHECK(mbx_abi_version() >= MBX_ABI_VERSION);
    mbx_context *ctx = NULL;
    if (mbx_context_create(&ctx) != MBX_OK) return 1;
    int rc = translate_arm(ctx, argv[1], argv[2]);
    if (rc == 0) rc = swing_pendulum(ctx);
    mbx_context_destroy(ctx);
    if (rc == 0 && failures == 0) printf("c_host: all checks passed\n");
    return rc != 0 ? rc : failures != 0;
}
