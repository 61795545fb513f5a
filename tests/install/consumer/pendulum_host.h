/*
 * A CAD host in plain C, as a consumer of the installed SDK writes one: a
 * compound pendulum served through the mbx_host callback table. A bob of
 * mass M hangs from a revolute joint about world x at the origin, its centre
 * of mass L below the pivot, inertia IC about its centre of mass. Its closed
 * forms (I = M L^2 + IC about the pivot, small-swing omega = sqrt(M g L / I))
 * are what the hosts check the simulation against.
 */
#ifndef PENDULUM_HOST_H
#define PENDULUM_HOST_H

#include <string.h>

#include <mbx/mbx.h>

#define PENDULUM_M 2.0
#define PENDULUM_L 0.5
#define PENDULUM_IC 0.01
#define PENDULUM_G 9.81

static int pendulum_body_count(void *u, size_t *n) { (void)u; *n = 2; return 0; }
static int pendulum_frame_count(void *u, size_t *n) { (void)u; *n = 2; return 0; }
static int pendulum_constraint_count(void *u, size_t *n) { (void)u; *n = 1; return 0; }

static void pendulum_identity(mbx_pose *pose) {
    memset(pose, 0, sizeof *pose);
    pose->rotation[0] = pose->rotation[4] = pose->rotation[8] = 1.0;
}

static int pendulum_get_body(void *u, size_t i, mbx_body_desc *out, char *msg, size_t msg_size) {
    (void)u; (void)msg; (void)msg_size;
    out->units.length_to_m = 1.0;
    out->units.mass_to_kg = 1.0;
    pendulum_identity(&out->pose);
    if (i == 0) {
        out->id = "ground";
        out->flags = MBX_BODY_GROUND;
        return 0;
    }
    out->id = "bob";
    out->mass = PENDULUM_M;
    out->com[2] = -PENDULUM_L;
    out->inertia[0] = out->inertia[4] = out->inertia[8] = PENDULUM_IC;
    return 0;
}

static int pendulum_get_frame(void *u, size_t i, mbx_frame_desc *out, char *msg, size_t msg_size) {
    (void)u; (void)msg; (void)msg_size;
    out->id = i == 0 ? "pivot_on_ground" : "pivot_on_bob";
    out->body_id = i == 0 ? "ground" : "bob";
    out->reference = MBX_FRAME_IN_WORLD;
    out->units.length_to_m = 1.0;
    pendulum_identity(&out->pose);
    return 0;
}

static int pendulum_get_constraint(void *u, size_t i, mbx_constraint_desc *out, char *msg, size_t msg_size) {
    (void)u; (void)i; (void)msg; (void)msg_size;
    out->id = "pivot";
    out->name = "pivot";
    out->base_frame_id = "pivot_on_ground";
    out->follower_frame_id = "pivot_on_bob";
    out->primitive_count = 1;
    return 0;
}

static int pendulum_get_primitive(void *u, size_t c, size_t p, mbx_primitive_desc *out, char *msg,
                                  size_t msg_size) {
    (void)u; (void)c; (void)p; (void)msg; (void)msg_size;
    out->type = MBX_PRIMITIVE_REVOLUTE;
    out->axis_reference = MBX_AXIS_IN_WORLD;
    out->axis[0] = 1.0;
    return 0;
}

static mbx_host pendulum_host(void) {
    mbx_host h;
    memset(&h, 0, sizeof h);
    h.struct_size = sizeof h;
    h.abi_version = MBX_HOST_ABI_VERSION;
    h.body_count = pendulum_body_count;
    h.get_body = pendulum_get_body;
    h.frame_count = pendulum_frame_count;
    h.get_frame = pendulum_get_frame;
    h.constraint_count = pendulum_constraint_count;
    h.get_constraint = pendulum_get_constraint;
    h.get_primitive = pendulum_get_primitive;
    return h;
}

#endif
