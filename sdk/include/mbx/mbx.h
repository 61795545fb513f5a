/*
 * mbx: turn a CAD assembly into a multibody mechanism.
 *
 * This header is the whole public contract of the mbx SDK. It is C99, uses no
 * C++ types, and every function returns an mbx_status. The shared library
 * exports only symbols that begin with "mbx_".
 *
 * ---------------------------------------------------------------------------
 * ABI RULES (what a host may rely on across SDK releases)
 * ---------------------------------------------------------------------------
 *  1. Every struct that crosses the boundary starts with `uint32_t struct_size`.
 *     The side that allocates the struct sets it to sizeof() as it was
 *     compiled. Fields are only ever APPENDED to the end of a struct; existing
 *     fields never move, change type or change meaning.
 *  2. A struct the HOST hands to the SDK (mbx_host, options) may be smaller
 *     than the SDK's current one: the SDK reads only the fields that lie
 *     within struct_size and uses documented defaults for the rest.
 *  3. A struct the SDK hands to the HOST to fill (descriptors in callbacks,
 *     query outputs) carries the capacity in struct_size; the filler writes
 *     only fields that lie within it (use MBX_FIELD_FITS).
 *  4. Enum values and status codes are never renumbered; new ones are added.
 *  5. MBX_ABI_VERSION is bumped whenever a field or function is appended.
 *     Functions are never removed from mbx_api; new ones are appended.
 *  6. Handles are opaque; their layout is not part of the ABI.
 *
 * ---------------------------------------------------------------------------
 * THREAD SAFETY
 * ---------------------------------------------------------------------------
 *  Independent contexts may be used concurrently from different threads; the
 *  SDK keeps no mutable global state. One context (and the mechanisms made
 *  with it) must not be used from two threads at the same time. Host
 *  callbacks are called only on the thread that called into the SDK.
 *
 * ---------------------------------------------------------------------------
 * UNITS AND CONVENTIONS
 * ---------------------------------------------------------------------------
 *  The host delivers values in its own units and states the SI factors in
 *  mbx_units; everything the SDK returns is SI (m, kg, kg*m^2, rad).
 *  Rotations are 3x3 matrices stored ROW-MAJOR: rotation[3*i+j] = R(i,j); the
 *  columns of R are the frame's axes expressed in the parent (world) frame.
 */
#ifndef MBX_H
#define MBX_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#  ifdef MBX_BUILDING_LIBRARY
#    define MBX_API __declspec(dllexport)
#  else
#    define MBX_API __declspec(dllimport)
#  endif
#else
#  define MBX_API __attribute__((visibility("default")))
#endif

#define MBX_VERSION_MAJOR 0
#define MBX_VERSION_MINOR 1
#define MBX_VERSION_PATCH 0
#define MBX_VERSION_STRING "0.1.0"

/* Bumped whenever a struct field or an mbx_api function is appended. */
#define MBX_ABI_VERSION 13u

/* True when `field` of the struct pointed to by `ptr` lies within the
 * struct_size the other side declared. */
#define MBX_FIELD_FITS(ptr, type, field) \
    ((ptr)->struct_size >= offsetof(type, field) + sizeof(((type *)0)->field))

/* ------------------------------------------------------------------------ */
/* Status codes                                                              */
/* ------------------------------------------------------------------------ */
typedef enum mbx_status {
    MBX_OK = 0,
    MBX_ERROR_INVALID_ARGUMENT = 1, /* NULL handle, bad struct_size, bad index */
    MBX_ERROR_HOST_CALLBACK = 2,    /* a host callback returned non-zero */
    MBX_ERROR_INVALID_INPUT = 3,    /* NaN, unknown reference, unusable data */
    MBX_ERROR_CANCELLED = 4,        /* the progress callback asked to stop */
    MBX_ERROR_IO = 5,               /* a file could not be written */
    MBX_ERROR_OUT_OF_MEMORY = 6,
    MBX_ERROR_VERSION = 7,          /* host table too old or from the future */
    MBX_ERROR_INTERNAL = 8,
    MBX_ERROR_SIMULATION = 9        /* a run diverged or its integrator failed (ABI 6) */
} mbx_status;

/* Static English name of a status ("MBX_ERROR_IO"). Never NULL. */
MBX_API const char *mbx_status_name(mbx_status status);

/* Library version string, e.g. "0.1.0". */
MBX_API const char *mbx_version(void);
/* ABI version this library implements (MBX_ABI_VERSION it was built with). */
MBX_API uint32_t mbx_abi_version(void);

/* ------------------------------------------------------------------------ */
/* Context and errors                                                        */
/* ------------------------------------------------------------------------ */
typedef struct mbx_context mbx_context;
typedef struct mbx_mechanism mbx_mechanism;

/* What a failure or a finding is about. */
typedef enum mbx_subject_kind {
    MBX_SUBJECT_NONE = 0,
    MBX_SUBJECT_BODY = 1,       /* a CAD part (host body) */
    MBX_SUBJECT_FRAME = 2,
    MBX_SUBJECT_CONSTRAINT = 3, /* a host constraint (a CAD joint) */
    MBX_SUBJECT_RIGID_BODY = 4, /* a translated rigid body */
    MBX_SUBJECT_LOOP = 5,
    MBX_SUBJECT_FILE = 6,
    MBX_SUBJECT_MODEL = 7
} mbx_subject_kind;

typedef enum mbx_severity {
    MBX_SEVERITY_INFO = 0,
    MBX_SEVERITY_WARNING = 1,
    MBX_SEVERITY_ERROR = 2
} mbx_severity;

typedef struct mbx_error_info {
    uint32_t struct_size;
    mbx_status status;
    mbx_subject_kind subject_kind;
    const char *subject_id;   /* stable id of the subject, "" if none */
    const char *subject_name; /* display name, "" if none */
    const char *file;         /* input file, "" if none */
    int32_t line;             /* 1-based line in `file`, 0 if unknown */
    const char *message;      /* full sentence naming the subject */
} mbx_error_info;

MBX_API mbx_status mbx_context_create(mbx_context **out_context);
MBX_API void mbx_context_destroy(mbx_context *context);

/* Message of the last failed call on this context ("" after success). The
 * pointer stays valid until the next call on the context. */
MBX_API const char *mbx_context_last_error(const mbx_context *context);
/* The same failure, structured. Strings live as long as the message. */
MBX_API mbx_status mbx_context_last_error_info(const mbx_context *context, mbx_error_info *out_info);

/* Progress: `stage` is a static string ("pull bodies", "merge welds", ...),
 * fraction in [0,1] within the stage. Return non-zero to cancel; the running
 * call then returns MBX_ERROR_CANCELLED and produces nothing. Long runs
 * (mbx_sim_run, mbx_calibrate, mbx_excite) call it by wall time, about every
 * 25 ms and always within 100 ms, whatever one step costs, and a cancel
 * takes effect within that; translation calls it every 1024 items. */
typedef int (*mbx_progress_fn)(void *user_data, const char *stage, double fraction);
MBX_API mbx_status mbx_context_set_progress(mbx_context *context, mbx_progress_fn progress, void *user_data);

/* ------------------------------------------------------------------------ */
/* Host interface: what the translator pulls from a CAD system               */
/* ------------------------------------------------------------------------ */

/* SI factors of the host's units: value_in_SI = value * factor. A factor of
 * 0 means "already SI" (1.0). inertia 0 means mass * length^2. */
typedef struct mbx_units {
    double length_to_m;
    double mass_to_kg;
    double inertia_to_kg_m2;
} mbx_units;

typedef struct mbx_pose {
    double position[3];
    double rotation[9]; /* row-major, see the header comment */
} mbx_pose;

typedef enum mbx_body_flags {
    MBX_BODY_GROUND = 1u << 0,   /* fixed to the world */
    MBX_BODY_HELPER = 1u << 1    /* massless CAD helper (e.g. "RootPart"):
                                    never a dynamic body of its own; with
                                    GROUND: a world datum, not a CAD part */
} mbx_body_flags;

/* One CAD part. Pose is in world coordinates at the assembly configuration.
 * The centre of mass and the inertia tensor (about the centre of mass) are
 * expressed in the body's own frame given by `pose`. */
typedef struct mbx_body_desc {
    uint32_t struct_size;
    const char *id;   /* stable, unique among bodies; required */
    const char *name; /* display name; may repeat; NULL = id */
    uint32_t flags;   /* mbx_body_flags */
    mbx_units units;
    double mass;
    double com[3];
    double inertia[9]; /* row-major, symmetric */
    mbx_pose pose;
    /* --- host ABI 4 --- */
    /* Solid volume of the part in the cube of its length unit (units.length_to_m),
     * as the CAD system computed it; 0 = unknown. With it the SDK checks that
     * mass / volume is a real material's density (MBX_FINDING_IMPLAUSIBLE_DENSITY). */
    double volume;
} mbx_body_desc;

typedef enum mbx_frame_reference {
    MBX_FRAME_IN_WORLD = 0, /* pose is in world coordinates */
    MBX_FRAME_IN_BODY = 1   /* pose is relative to the owning body's pose */
} mbx_frame_reference;

typedef struct mbx_frame_desc {
    uint32_t struct_size;
    const char *id;      /* stable, unique among frames; required */
    const char *name;
    const char *body_id; /* owning body; required */
    mbx_frame_reference reference;
    mbx_units units;     /* only length_to_m is used */
    mbx_pose pose;
} mbx_frame_desc;

typedef enum mbx_primitive_type {
    MBX_PRIMITIVE_WELD = 0,
    MBX_PRIMITIVE_PRISMATIC = 1,
    MBX_PRIMITIVE_REVOLUTE = 2,
    MBX_PRIMITIVE_SPHERICAL = 3
} mbx_primitive_type;

typedef enum mbx_axis_reference {
    MBX_AXIS_IN_WORLD = 0,     /* axis components in world axes */
    MBX_AXIS_IN_BASE_FRAME = 1 /* axis components in the base frame's axes */
} mbx_axis_reference;

/* One primitive of a constraint chain. Limits: radians for revolute; for
 * prismatic, the length unit of the constraint's base frame. */
typedef struct mbx_primitive_desc {
    uint32_t struct_size;
    mbx_primitive_type type;
    mbx_axis_reference axis_reference;
    double axis[3]; /* ignored for weld and spherical */
    int32_t has_limits;
    double lower;
    double upper;
    /* ABI 12: the joint's rated speed and effort in SI (rad/s or m/s; N m or
     * N), as a URDF's <limit velocity effort> gives them; 0: not given. The
     * exports write them where the format has a place for them. */
    double velocity_limit;
    double effort_limit;
} mbx_primitive_desc;

/* A CAD joint: Base -> J_N ... J_1 -> Follower. Primitive index 0 is J_N
 * (next to the base), the last one is J_1 (next to the follower). */
typedef struct mbx_constraint_desc {
    uint32_t struct_size;
    const char *id;   /* stable, unique among constraints; required */
    const char *name;
    const char *base_frame_id;
    const char *follower_frame_id;
    uint32_t primitive_count; /* >= 1 */
    const char *host_status;  /* host's diagnostic ("Could not solve..."), "" or NULL if none */
} mbx_constraint_desc;

/* Triangle mesh, in the host's length unit, expressed in `pose` relative to
 * the owning body's frame. Arrays are only read during add_mesh. */
typedef struct mbx_mesh_desc {
    uint32_t struct_size;
    const char *name;
    mbx_units units;         /* only length_to_m is used */
    mbx_pose pose;           /* mesh frame relative to the body frame */
    const double *vertices;  /* 3 * vertex_count */
    uint32_t vertex_count;
    const uint32_t *triangles; /* 3 * triangle_count, 0-based */
    uint32_t triangle_count;
    /* ABI 12: the colour the CAD model shows the mesh in, red green blue
     * alpha in 0..1; alpha 0 (a zeroed field, or an older host): none given,
     * drawn in the exports' default grey. */
    double color[4];
} mbx_mesh_desc;

/* Where a host delivers the shapes of one body. */
typedef struct mbx_shape_sink {
    uint32_t struct_size;
    void *sink_data;
    /* Returns non-zero if the mesh was rejected; the host should then stop
     * and return non-zero from get_shapes. */
    int (*add_mesh)(void *sink_data, const mbx_mesh_desc *mesh);
} mbx_shape_sink;

/* Something the host itself noticed while preparing its data (a missing mesh
 * file, an unmatched VRML shape, a parse warning). The SDK copies it into the
 * mechanism's findings as MBX_FINDING_HOST_DIAGNOSTIC, keeping `code`. */
typedef struct mbx_host_diagnostic {
    uint32_t struct_size;
    mbx_severity severity;
    const char *code;         /* short stable name, e.g. "mesh_file_missing"; NULL = "host_diagnostic" */
    mbx_subject_kind subject_kind;
    const char *subject_id;
    const char *subject_name;
    const char *file;         /* input file, NULL if none */
    int32_t line;             /* 1-based, 0 if unknown */
    const char *message;
} mbx_host_diagnostic;

#define MBX_HOST_ABI_VERSION 4u

/*
 * The callback table a CAD host implements (as sqlite3_vfs). Callbacks return
 * 0 on success and non-zero on failure; after a failure the host may place a
 * message in `message` (capacity `message_size`), which the SDK reports.
 * Descriptors are zeroed by the SDK with struct_size set before the call.
 * Strings returned inside descriptors must stay valid until the next callback
 * into the same host; the SDK copies them.
 *
 * Version 1 ends at get_shapes. Version 2 appended describe_assembly,
 * version 3 diagnostic_count and get_diagnostic, version 4 the body volume
 * (mbx_body_desc.volume) and get_assembly_mass. From version 4 on, a host may
 * append diagnostics (never change or drop earlier ones) while it serves
 * get_shapes, e.g. for a mesh file that only fails when it is loaded; after
 * each get_shapes call the SDK pulls the new ones into the mechanism's
 * findings. The diagnostics of an older host are pulled once.
 * The table must stay valid, and its callbacks callable, for as long as a
 * mechanism created from it may still ask for shapes (until
 * mbx_mechanism_destroy or mbx_mechanism_release_host).
 */
typedef struct mbx_host {
    uint32_t struct_size; /* sizeof(mbx_host) as the host was compiled */
    uint32_t abi_version; /* MBX_HOST_ABI_VERSION the host was compiled with */
    void *user_data;

    /* --- version 1 --- */
    int (*body_count)(void *user_data, size_t *out_count);
    int (*get_body)(void *user_data, size_t index, mbx_body_desc *out, char *message, size_t message_size);
    int (*frame_count)(void *user_data, size_t *out_count);
    int (*get_frame)(void *user_data, size_t index, mbx_frame_desc *out, char *message, size_t message_size);
    int (*constraint_count)(void *user_data, size_t *out_count);
    int (*get_constraint)(void *user_data, size_t index, mbx_constraint_desc *out, char *message,
                          size_t message_size);
    int (*get_primitive)(void *user_data, size_t constraint_index, size_t primitive_index,
                         mbx_primitive_desc *out, char *message, size_t message_size);
    /* Optional (may be NULL): deliver the meshes of body `body_id` to `sink`.
     * Called lazily, only when a consumer needs geometry. */
    int (*get_shapes)(void *user_data, const char *body_id, const mbx_shape_sink *sink, char *message,
                      size_t message_size);

    /* --- version 2 --- */
    /* Optional (may be NULL): the assembly's name and source, for reports. */
    int (*describe_assembly)(void *user_data, const char **out_name, const char **out_source);

    /* --- version 3 --- */
    /* Optional (both or neither): the host's own diagnostics, pulled once
     * before the bodies. */
    int (*diagnostic_count)(void *user_data, size_t *out_count);
    int (*get_diagnostic)(void *user_data, size_t index, mbx_host_diagnostic *out);

    /* --- version 4 --- */
    /* Optional (may be NULL): the whole assembly's mass as the CAD system
     * states it, in kg; return non-zero (or leave 0) if it states none. The
     * SDK compares it with the sum of the parts' masses
     * (MBX_FINDING_ASSEMBLY_MASS_MISMATCH). */
    int (*get_assembly_mass)(void *user_data, double *out_mass_kg);
} mbx_host;

/* Size of the version-1 table, for hosts and tests that need it. */
#define MBX_HOST_V1_SIZE (offsetof(mbx_host, describe_assembly))

/* ------------------------------------------------------------------------ */
/* Translation                                                               */
/* ------------------------------------------------------------------------ */
typedef struct mbx_translate_options {
    uint32_t struct_size;
    /* Positions closer than this (metres) coincide. 0 = automatic:
     * 1e-5 times the assembly's bounding-box diagonal, at least 1e-9 m. */
    double length_tolerance;
    /* Rotation matrices whose max |R^T R - I| exceeds this are reported when
     * re-orthonormalized. 0 = 1e-5 (six significant digits round to ~1e-6). */
    double orthonormality_tolerance;
    /* Relative singular-value threshold for the loop-closure Jacobian rank.
     * 0 = 1e-6. */
    double rank_tolerance;
    /* --- ABI 3 --- */
    uint32_t flags; /* mbx_translate_flags */
    /* Centroid mismatch (metres) above which MBX_FINDING_MASS_MISMATCH is a
     * warning. 0 = max(1 mm, 2 % of the part's mesh bounding-box diagonal). */
    double centroid_tolerance;
} mbx_translate_options;

typedef enum mbx_translate_flags {
    /* Ask the host for every part's shapes during translation and compare the
     * closed meshes' volume centroid with the CAD centre of mass. */
    MBX_TRANSLATE_CHECK_MASS_WITH_SHAPES = 1u << 0
} mbx_translate_flags;

/* Pull the assembly through `host` and build the mechanism. On success
 * *out_mechanism owns the result (findings included); on failure nothing is
 * produced and the context's error says what and where. `options` may be
 * NULL for defaults. */
MBX_API mbx_status mbx_translate(mbx_context *context, const mbx_host *host,
                                 const mbx_translate_options *options, mbx_mechanism **out_mechanism);

MBX_API void mbx_mechanism_destroy(mbx_mechanism *mechanism);

/* Forget the host: later shape requests fail with MBX_ERROR_INVALID_ARGUMENT.
 * Call before the host table or its user data goes away. */
MBX_API mbx_status mbx_mechanism_release_host(mbx_mechanism *mechanism);

/* ------------------------------------------------------------------------ */
/* Querying a mechanism (flat, index-based, as MuJoCo's mj_ API)             */
/* ------------------------------------------------------------------------ */
typedef struct mbx_mechanism_summary {
    uint32_t struct_size;
    uint32_t part_count;          /* CAD bodies pulled from the host */
    uint32_t rigid_body_count;    /* dynamic rigid bodies after weld merging (ground excluded) */
    uint32_t joint_node_count;    /* massless intermediate nodes of joint chains */
    uint32_t joint_count;         /* primitive joints (tree + cut), welds excluded */
    uint32_t revolute_count;
    uint32_t prismatic_count;
    uint32_t spherical_count;
    uint32_t weld_count;          /* weld constraints merged away */
    uint32_t cut_joint_count;
    uint32_t loop_count;          /* independent loops = cut joints */
    uint32_t planar_loop_count;
    uint32_t collapsed_weld_loop_count;
    int32_t dof;                  /* numeric mobility of the whole mechanism */
    int32_t gruebler_dof;         /* Gruebler-Kutzbach count */
    uint32_t redundant_constraint_count;
    uint32_t floating_body_count; /* tree roots not attached to ground (6 DoF each) */
    uint32_t warning_count;
    uint32_t error_count;
    /* --- ABI 3 --- */
    /* part_count less world datums: bodies flagged both GROUND and HELPER
     * (e.g. PMXML's RootGround) that stand for the world, not a CAD part. */
    uint32_t cad_part_count;
} mbx_mechanism_summary;

MBX_API mbx_status mbx_mechanism_get_summary(const mbx_mechanism *mechanism, mbx_mechanism_summary *out);

/* Rigid body 0 is the ground; then dynamic bodies, then joint nodes. */
typedef enum mbx_rigid_body_kind {
    MBX_RIGID_BODY_GROUND = 0,
    MBX_RIGID_BODY_DYNAMIC = 1,
    MBX_RIGID_BODY_JOINT_NODE = 2
} mbx_rigid_body_kind;

typedef struct mbx_rigid_body_info {
    uint32_t struct_size;
    mbx_rigid_body_kind kind;
    const char *name;       /* name of the principal part, or of the node */
    const char *id;         /* id of the principal part, or "<constraint id>#<k>" */
    uint32_t part_count;    /* CAD parts merged into this body */
    double mass;
    double com[3];          /* in the body frame */
    double inertia[9];      /* about com, body axes, row-major */
    mbx_pose pose;          /* world, at the assembly configuration (SI) */
    int32_t parent_joint;   /* index of the tree joint above it, -1 for roots */
} mbx_rigid_body_info;

MBX_API mbx_status mbx_mechanism_get_rigid_body(const mbx_mechanism *mechanism, uint32_t index,
                                                mbx_rigid_body_info *out);
/* Index of the rigid body a CAD part ended up in. */
MBX_API mbx_status mbx_mechanism_find_part(const mbx_mechanism *mechanism, const char *part_id,
                                           uint32_t *out_rigid_body);

typedef struct mbx_joint_info {
    uint32_t struct_size;
    mbx_primitive_type type;
    const char *name;          /* "<constraint name>" or "<constraint name>#k" for chains */
    const char *constraint_id; /* host constraint it came from */
    uint32_t primitive_index;  /* position in the host chain (0 = J_N) */
    uint32_t parent;           /* rigid body on the tree-parent side */
    uint32_t child;            /* rigid body on the tree-child side */
    int32_t is_cut;            /* 1: loop-closing (cut) joint, not a tree edge */
    int32_t reversed;          /* 1: parent side is the CAD follower side */
    double axis[3];            /* unit axis in world at the assembly pose */
    mbx_pose frame;            /* joint frame in world at the assembly pose */
    int32_t has_limits;
    double lower, upper;       /* SI */
    int32_t loop;              /* loop this cut joint closes, -1 for tree joints */
} mbx_joint_info;

MBX_API mbx_status mbx_mechanism_get_joint(const mbx_mechanism *mechanism, uint32_t index, mbx_joint_info *out);

typedef struct mbx_loop_info {
    uint32_t struct_size;
    uint32_t cut_joint;        /* joint index */
    uint32_t joint_count;      /* primitive joints around the loop (cut included) */
    int32_t dof;               /* numeric mobility of this loop alone */
    int32_t gruebler_dof;      /* sum f - 6 (or - 3 if planar) */
    uint32_t redundant;        /* rank deficit of its 6 closure equations */
    int32_t planar;            /* 1: all axes parallel revolutes / normal prismatics */
    double planar_normal[3];   /* world normal of the loop plane if planar */
} mbx_loop_info;

MBX_API mbx_status mbx_mechanism_get_loop(const mbx_mechanism *mechanism, uint32_t index, mbx_loop_info *out);
/* Joint indices around loop `index`; *inout_count is the capacity in and the
 * needed count out (call with 0 to ask). */
MBX_API mbx_status mbx_mechanism_get_loop_joints(const mbx_mechanism *mechanism, uint32_t index,
                                                 uint32_t *joints, uint32_t *inout_count);

/* Stable finding codes; the report writes their names (mbx_finding_code_name). */
typedef enum mbx_finding_code {
    MBX_FINDING_INERTIA_NOT_POSITIVE_DEFINITE = 1,
    MBX_FINDING_INERTIA_TRIANGLE_INEQUALITY = 2,
    MBX_FINDING_JOINT_FRAMES_APART = 3,
    MBX_FINDING_BODY_UNCONNECTED = 4,
    MBX_FINDING_ZERO_MASS_BODY = 5,
    MBX_FINDING_ROTATION_REORTHONORMALIZED = 6,
    MBX_FINDING_HOST_STATUS = 7,
    MBX_FINDING_WELD_LOOP_COLLAPSED = 8,
    MBX_FINDING_REDUNDANT_CONSTRAINTS = 9,
    MBX_FINDING_FLOATING_SUBASSEMBLY = 10,
    MBX_FINDING_HELPER_BODY_DROPPED = 11,
    MBX_FINDING_PLANAR_LOOP = 12,
    MBX_FINDING_MOBILITY_MISMATCH = 13,
    MBX_FINDING_DEGENERATE_AXIS = 14,
    MBX_FINDING_SELF_CONSTRAINT = 15,
    MBX_FINDING_NEGATIVE_MASS = 16,
    MBX_FINDING_LIMITS_INVERTED = 17,
    MBX_FINDING_HOST_DIAGNOSTIC = 18, /* code_name carries the host's code */
    MBX_FINDING_MASS_MISMATCH = 19,   /* CAD centre of mass far from the mesh centroid */
    MBX_FINDING_SHAPE_NOT_CLOSED = 20, /* mesh cannot be checked: not a closed surface */
    /* ABI 4: notes from mbx_mechanism_export */
    MBX_FINDING_EXPORT_LOOPS_AS_TREE = 21,    /* target has no loops: spanning tree + cut-joint sidecar */
    MBX_FINDING_EXPORT_APPROXIMATION = 22,    /* target cannot express something exactly; says what changed */
    MBX_FINDING_EXPORT_MESH_MISSING = 23,     /* a body's geometry could not be loaded; exported without it */
    /* ABI 9 */
    MBX_FINDING_IMPLAUSIBLE_DENSITY = 24,     /* CAD mass / CAD volume is no real material's density */
    MBX_FINDING_ASSEMBLY_MASS_MISMATCH = 25   /* host's assembly mass far from the sum of its parts */
} mbx_finding_code;

typedef struct mbx_finding {
    uint32_t struct_size;
    mbx_severity severity;
    mbx_finding_code code;
    mbx_subject_kind subject_kind;
    const char *subject_id;
    const char *subject_name;
    const char *message;
    /* --- ABI 3 --- */
    const char *code_name; /* mbx_finding_code_name(code), or the host's code */
    const char *file;      /* "" if none */
    int32_t line;          /* 0 if unknown */
} mbx_finding;

MBX_API const char *mbx_finding_code_name(mbx_finding_code code);
MBX_API uint32_t mbx_mechanism_finding_count(const mbx_mechanism *mechanism);
MBX_API mbx_status mbx_mechanism_get_finding(const mbx_mechanism *mechanism, uint32_t index, mbx_finding *out);

/* ------------------------------------------------------------------------ */
/* Shapes (lazy)                                                             */
/* ------------------------------------------------------------------------ */
typedef struct mbx_shape_stats {
    uint32_t struct_size;
    uint32_t mesh_count;
    uint64_t vertex_count;
    uint64_t triangle_count;
    double bounds_min[3]; /* body frame, metres */
    double bounds_max[3];
} mbx_shape_stats;

/* Asks the host (once, then cached) for the meshes of every part of rigid
 * body `index` and returns their totals in the body frame. */
MBX_API mbx_status mbx_mechanism_get_shape_stats(mbx_context *context, mbx_mechanism *mechanism, uint32_t index,
                                                 mbx_shape_stats *out);

/* ------------------------------------------------------------------------ */
/* Reports                                                                   */
/* ------------------------------------------------------------------------ */
/* Writes <directory>/report.json and <directory>/report.txt. Each file is
 * written to a temporary name and renamed, so a reader never sees half a
 * report. The directory is created if missing. */
MBX_API mbx_status mbx_mechanism_write_report(mbx_context *context, const mbx_mechanism *mechanism,
                                              const char *directory);

/* ------------------------------------------------------------------------ */
/* Export (ABI 4)                                                            */
/* ------------------------------------------------------------------------ */
typedef enum mbx_export_format {
    MBX_EXPORT_MODELICA = 1u << 0, /* modelica/<Name>/: MSL 4.0 MultiBody package */
    MBX_EXPORT_MJCF = 1u << 1,     /* mjcf/<name>.xml: MuJoCo, loops closed by equality constraints */
    MBX_EXPORT_URDF = 1u << 2,     /* urdf/<name>.urdf: spanning tree (+ cut_joints.json with loops) */
    MBX_EXPORT_MESHES = 1u << 3,   /* meshes/<body>.<ext> and scene.glb */
    MBX_EXPORT_ALL = 0xFu,
    /* ABI 9, a modifier outside ALL (opt-in): scene.glb also draws the described collision shapes as
       semi-transparent nodes "collision_<shape>" under their bodies' nodes */
    MBX_EXPORT_SCENE_COLLISION = 1u << 4
} mbx_export_format;

typedef enum mbx_mesh_format {
    MBX_MESH_STL = 0, /* binary STL */
    MBX_MESH_OBJ = 1,
    MBX_MESH_GLTF = 2 /* binary glTF 2.0 (.glb, one self-contained file) */
} mbx_mesh_format;

typedef struct mbx_export_options {
    uint32_t struct_size;
    uint32_t formats;            /* mbx_export_format bits; 0 = all */
    mbx_mesh_format mesh_format; /* for meshes/; MJCF and URDF use STL unless OBJ is chosen */
    const char *model_name;      /* NULL or "": "model"; sanitized per target */
    double stop_time;            /* Modelica experiment StopTime, s; <= 0: 10 */
} mbx_export_options;

/* Exports the mechanism below `directory` (created if missing). Every file is
 * written to a temporary and all are renamed together at the end, so a
 * failure leaves the directory as it was. Re-exporting the same mechanism
 * gives byte-identical files; the Modelica user model (modelica/<Name>/
 * UserModel.mo) is written only if absent, so the user's edits survive.
 * What a target cannot express is added to the mechanism's findings
 * (MBX_FINDING_EXPORT_*) and so appears in a report written afterwards.
 * Geometry is fetched from the host if it has not been released. */
MBX_API mbx_status mbx_mechanism_export(mbx_context *context, mbx_mechanism *mechanism,
                                        const mbx_export_options *options, const char *directory);

/* ABI 12. Writes the URDF `urdf_path` the mechanism was translated from to
 * `output_path` (a temporary renamed over it, so it may equal urdf_path)
 * with the mechanism's attached joint dynamics and body mass corrections in
 * it: <dynamics damping friction> of every joint with joint dynamics, the
 * <inertial> of the links of every corrected body. Only values that differ
 * change; every other byte (layout, comments, unknown tags) stays as it was.
 * What URDF cannot hold (armature, springs, asymmetric friction) is added to
 * the mechanism's findings. Fails with MBX_ERROR_INVALID_INPUT naming the
 * file, line and link or joint when the file is not the one the mechanism
 * was read from (docs/urdf.md). */
MBX_API mbx_status mbx_mechanism_update_urdf(mbx_context *context, mbx_mechanism *mechanism, const char *urdf_path,
                                            const char *output_path);

/* ------------------------------------------------------------------------ */
/* Mechatronics (ABI 5): object library, drives, motion targets              */
/* ------------------------------------------------------------------------ */
/* What a user adds to the CAD model (thesis section 2.8): DC motors and
 * transmissions drawn from an XML object library, assigned to joints by the
 * joint's stable CAD id, with an amplifier, a position controller and a
 * motion target. An mbx_mechatronics object holds these independently of any
 * mechanism, so the same assignment is re-applied after the CAD model
 * changes; mbx_mechanism_set_mechatronics resolves it against a mechanism,
 * and exports then include the drives (docs/mechatronics.md). */
typedef struct mbx_mechatronics mbx_mechatronics;

typedef enum mbx_amplifier_mode {
    MBX_AMPLIFIER_VOLTAGE = 0, /* controller output = armature voltage (V) */
    MBX_AMPLIFIER_CURRENT = 1  /* armature current = amplifier_gain * output */
} mbx_amplifier_mode;

typedef enum mbx_velocity_estimate {
    MBX_VELOCITY_MEASURED = 0,           /* true joint velocity (continuous controllers) */
    MBX_VELOCITY_DIFFERENCE = 1,         /* (q_k - q_k-1) / Ts */
    MBX_VELOCITY_FILTERED_DIFFERENCE = 2 /* difference of (q_k + q_k-1) / 2 */
} mbx_velocity_estimate;

/* Position loop on e = target - q (joint units, rad or m):
 *   u_p = kp e + ki integral(e) - kd qdot
 * with a velocity loop (kv > 0): u = kv (u_p - qdot) + kvi integral(u_p - qdot),
 * else u = u_p; then |u| <= output_limit (0: VaNominal in voltage mode) and a
 * transport delay. sample_period 0 = continuous time. */
typedef struct mbx_controller_desc {
    uint32_t struct_size;
    double kp, ki, kd;
    double kv, kvi;
    double sample_period; /* s, 0 = continuous */
    double delay;         /* s; whole samples for a discrete controller */
    double output_limit;
    mbx_velocity_estimate velocity_estimate;
} mbx_controller_desc;

/* An editable library parameter overridden for one drive, in the unit its
 * class declares. (Fixed layout: it is used in arrays.) */
typedef struct mbx_parameter_override {
    const char *name;
    double value;
} mbx_parameter_override;

typedef struct mbx_drive_desc {
    uint32_t struct_size;
    const char *name;            /* NULL or "": the joint's name */
    const char *constraint_id;   /* the CAD joint (host constraint id); required */
    int32_t primitive_index;     /* position in its chain; -1: its only prismatic/revolute primitive */
    const char *motor_id;        /* object library ID of a dc_motor object; required */
    const char *transmission_id; /* gearbox or ball_screw object ID; NULL or "": none */
    mbx_amplifier_mode amplifier_mode;
    double amplifier_gain;       /* A per unit of output (current mode) */
    const mbx_controller_desc *controller; /* required */
    const mbx_parameter_override *overrides;
    uint32_t override_count;
} mbx_drive_desc;

typedef enum mbx_interpolation {
    MBX_INTERPOLATION_LINEAR = 0,
    MBX_INTERPOLATION_SMOOTH = 1, /* rest-to-rest quintic between points */
    MBX_INTERPOLATION_STEP = 2
} mbx_interpolation;

typedef struct mbx_motion_point {
    double time;  /* s, strictly increasing */
    double value; /* rad or m (SI) */
} mbx_motion_point;

MBX_API mbx_status mbx_mechatronics_create(mbx_context *context, mbx_mechatronics **out_mechatronics);
MBX_API void mbx_mechatronics_destroy(mbx_mechatronics *mechatronics);
/* Loads an object library file (docs/object_library.md). Every problem of the
 * file is in the error message, one per line ("file:line: class/object:
 * message"); the structured error names the first. Nothing of a file with
 * problems is kept. */
MBX_API mbx_status mbx_mechatronics_load_library(mbx_context *context, mbx_mechatronics *mechatronics,
                                                 const char *path);
/* The same from text in memory; `name` stands for the file in messages. */
MBX_API mbx_status mbx_mechatronics_load_library_text(mbx_context *context, mbx_mechatronics *mechatronics,
                                                      const char *text, const char *name);
/* Loads a drive description file (docs/mechatronics.md) and the libraries it
 * names. Errors as for libraries; nothing of a file with problems is kept. */
MBX_API mbx_status mbx_mechatronics_load_drives(mbx_context *context, mbx_mechatronics *mechatronics,
                                                const char *path);
/* (ABI 11) The same from text: `name` names it in messages; libraries it
 * names are found relative to the current directory. A file adapter's own
 * description of its input (a URDF's joint dynamics and collision shapes)
 * arrives this way, before the user's description file refines it. */
MBX_API mbx_status mbx_mechatronics_load_drives_text(mbx_context *context, mbx_mechatronics *mechatronics,
                                                     const char *text, const char *name);
/* Adds one drive (replacing a drive on the same joint). Checked for form
 * here, against the library and the mechanism by mbx_mechanism_set_mechatronics. */
MBX_API mbx_status mbx_mechatronics_add_drive(mbx_context *context, mbx_mechatronics *mechatronics,
                                              const mbx_drive_desc *drive);
/* Sets the motion target of the drive on (constraint_id, primitive_index);
 * count 0 holds 0. The drive must have been added. */
MBX_API mbx_status mbx_mechatronics_set_motion(mbx_context *context, mbx_mechatronics *mechatronics,
                                               const char *constraint_id, int32_t primitive_index,
                                               const mbx_motion_point *points, uint32_t count,
                                               mbx_interpolation interpolation);
MBX_API uint32_t mbx_mechatronics_drive_count(const mbx_mechatronics *mechatronics);

/* Joint dynamics of one revolute or prismatic joint (ABI 6, grown in 7), SI: what the
 * description file's <joint> element holds (docs/mechatronics.md). They act
 * in the simulator and every export carries them. */
typedef struct mbx_joint_dynamics_desc {
    uint32_t struct_size;
    const char *constraint_id;  /* the CAD joint; required */
    int32_t primitive_index;    /* position in its chain; -1: its only prismatic/revolute primitive */
    double damping;             /* N m s/rad or N s/m */
    double coulomb;             /* friction effort while sliding, N m or N */
    double coulomb_velocity;    /* regularisation speed of the fixed-step law; 0: the simulator's default */
    double stiffness;           /* N m/rad or N/m, about `rest` */
    double rest;                /* rad or m */
    double armature;            /* kg m^2 or kg, added to the joint's inertia (and to a drive's) */
    int32_t limited;            /* 1: lower/upper replace the CAD joint's limits */
    double lower, upper;        /* rad or m */
    /* --- ABI 7 --- */
    double offset;              /* N m or N, any sign: constant effort the actuator supplies; acts as -offset */
    double coulomb_negative;    /* with asymmetric = 1: Coulomb friction for q' < 0 (coulomb holds for q' > 0) */
    double damping_negative;    /* with asymmetric = 1: damping for q' < 0 (damping holds for q' > 0) */
    double stribeck;            /* N m or N: static friction above the Coulomb level */
    double stribeck_velocity;   /* rad/s or m/s: its decay speed, > 0 when stribeck > 0 */
    int32_t asymmetric;         /* 1: coulomb_negative and damping_negative apply; 0 (a zeroed struct): symmetric */
} mbx_joint_dynamics_desc;

/* Sets the joint dynamics of (constraint_id, primitive_index), replacing
 * earlier ones on that joint. MBX_ERROR_INVALID_INPUT for a negative or
 * non-finite coefficient or lower > upper; checked against the mechanism by
 * mbx_mechanism_set_mechatronics (unknown, weld, spherical or cut joint). */
MBX_API mbx_status mbx_mechatronics_set_joint_dynamics(mbx_context *context, mbx_mechatronics *mechatronics,
                                                       const mbx_joint_dynamics_desc *dynamics);

/* A body's inertia corrected (ABI 10), SI: what the description file's
 * <body> element holds (docs/mechatronics.md), e.g. what `mbx calibrate`
 * identified. Relative to the CAD values: the whole inertia times
 * mass_scale, then the centre of mass moved by com_shift (body frame, the
 * inertia about it unchanged) and inertia_change added to the inertia tensor
 * about the centre of mass (body axes). */
typedef struct mbx_body_correction_desc {
    uint32_t struct_size;
    const char *body_id;        /* the body's CAD part id, or any part merged into it; required */
    double mass_scale;          /* > 0; 0 in a zeroed struct means 1 */
    double com_shift[3];        /* m */
    double inertia_change[6];   /* kg m^2: xx yy zz xy xz yz */
} mbx_body_correction_desc;

/* Sets the correction of one body, replacing an earlier one for the same
 * id. MBX_ERROR_INVALID_INPUT for a non-finite value or a negative scale;
 * checked against the mechanism by mbx_mechanism_set_mechatronics (unknown
 * body, a body without mass, a corrected inertia no rigid body can have). */
MBX_API mbx_status mbx_mechatronics_set_body_correction(mbx_context *context, mbx_mechatronics *mechatronics,
                                                        const mbx_body_correction_desc *correction);

/* Resolves every drive and every joint's dynamics against the mechanism
 * and attaches them (replacing earlier ones; NULL detaches). Fails with MBX_ERROR_INVALID_INPUT, attaching
 * nothing, when a drive names an unknown constraint, a joint that cannot be
 * driven (weld, spherical, cut) or driven twice, a missing library object or
 * one of the wrong kind, an override that is not editable or out of bounds,
 * or an unusable controller; the message lists every problem. The mechanism
 * keeps its own copy: `mechatronics` may be destroyed afterwards. */
MBX_API mbx_status mbx_mechanism_set_mechatronics(mbx_context *context, mbx_mechanism *mechanism,
                                                  const mbx_mechatronics *mechatronics);

/* A resolved drive: every quantity at the joint, the same in every export. */
typedef struct mbx_drive_info {
    uint32_t struct_size;
    const char *name;
    uint32_t joint;             /* mbx_mechanism_get_joint index */
    int32_t linear;             /* 1: prismatic (efforts N, inertia kg) */
    const char *motor_name;
    const char *transmission_name; /* "" when none */
    double ratio;               /* motor rad per joint rad (or per m) */
    double efficiency;
    double armature;            /* rotor + transmission inertia at the joint */
    double effort_limit;        /* N m or N at the joint */
    double velocity_limit;      /* rad/s or m/s at the joint */
    double output_limit;        /* controller output bound (V or amplifier units) */
    double torque_constant;     /* N m/A = V s/rad */
    double stall_torque;        /* motor shaft, at VaNominal */
    double no_load_speed;       /* motor shaft, rad/s at VaNominal */
    double rotor_inertia;       /* kg m^2 */
    double servo_stiffness;     /* equivalent continuous servo at the joint (docs/mechatronics.md) */
    double servo_damping;
    double emf_damping;         /* back-EMF braking, voltage mode */
    uint32_t motion_point_count;
} mbx_drive_info;

MBX_API uint32_t mbx_mechanism_drive_count(const mbx_mechanism *mechanism);
MBX_API mbx_status mbx_mechanism_get_drive(const mbx_mechanism *mechanism, uint32_t index, mbx_drive_info *out);
/* Motion target of drive `index` at `time`: position, velocity, acceleration
 * (SI) written to out[0..2]. */
MBX_API mbx_status mbx_mechanism_drive_target(const mbx_mechanism *mechanism, uint32_t index, double time,
                                              double out[3]);

/* ------------------------------------------------------------------------ */
/* Simulation (ABI 6): mbx's own forward dynamics of a mechanism             */
/* ------------------------------------------------------------------------ */
/* A simulation model is built once from a translated mechanism (with the
 * drives attached to it) and is then constant; any number of simulation
 * data objects (state, inputs, workspaces) may share it, one per rollout.
 * Coordinates are reduced (joint) coordinates along the mechanism's spanning
 * tree, zero at the CAD assembly pose, as in every export:
 *   revolute q = angle (rad), prismatic q = displacement (m), 1 velocity;
 *   spherical q = unit quaternion w x y z, v = angular velocity in the
 *     child-side joint frame (3);
 *   free (one per floating body) q = world position x y z then quaternion,
 *     v = world velocity of the body origin, then angular velocity in the
 *     body frame (MuJoCo's convention).
 * Cut joints close their loops as constraints. Gravity defaults to 9.81
 * m/s^2 along -z. See docs/simulation.md. */
typedef struct mbx_sim_model mbx_sim_model;
typedef struct mbx_sim_data mbx_sim_data;

typedef enum mbx_integrator {
    MBX_INTEGRATOR_RK4 = 0,      /* fixed step, 4th order */
    MBX_INTEGRATOR_EULER = 1,    /* fixed step, semi-implicit Euler */
    MBX_INTEGRATOR_ACCURATE = 2  /* variable step with error control (CVODE), stick/slip friction */
} mbx_integrator;

#define MBX_SIM_SET_GRAVITY 1u /* mbx_sim_options.flags: use gravity[] */

typedef struct mbx_sim_options {
    uint32_t struct_size;
    uint32_t flags;            /* MBX_SIM_SET_GRAVITY */
    double gravity[3];         /* m/s^2, world */
    mbx_integrator integrator; /* default RK4 */
    double step;               /* s; fixed step, or the accurate mode's largest step; 0: 1e-3 */
    double tolerance;          /* accurate mode relative tolerance; 0: 1e-8 */
} mbx_sim_options;

/* Builds the model of `mechanism` with its attached drives. Fails with
 * MBX_ERROR_INVALID_INPUT naming the joint for unusable joint dynamics. */
MBX_API mbx_status mbx_sim_model_create(mbx_context *context, const mbx_mechanism *mechanism,
                                        const mbx_sim_options *options, mbx_sim_model **out_model);
/* Destroy data objects first. */
MBX_API void mbx_sim_model_destroy(mbx_sim_model *model);

typedef struct mbx_sim_model_info {
    uint32_t struct_size;
    uint32_t nq, nv;             /* position and velocity coordinates */
    uint32_t joint_count;        /* simulated joints (tree joints and free joints) */
    uint32_t drive_count;
    uint32_t loop_closure_count; /* cut joints */
    uint32_t closure_rows;       /* constraint rows, redundant ones included */
    double gravity[3];
} mbx_sim_model_info;

typedef enum mbx_sim_joint_kind {
    MBX_SIM_JOINT_REVOLUTE = 0,
    MBX_SIM_JOINT_PRISMATIC = 1,
    MBX_SIM_JOINT_SPHERICAL = 2,
    MBX_SIM_JOINT_FIXED = 3, /* a weld primitive inside a CAD joint chain: no coordinates */
    MBX_SIM_JOINT_FREE = 4
} mbx_sim_joint_kind;

typedef struct mbx_sim_joint_info {
    uint32_t struct_size;
    const char *name;          /* the report's joint name; a floating body's name for a free joint */
    const char *constraint_id; /* CAD constraint id; the body id for a free joint */
    mbx_sim_joint_kind kind;
    int32_t mechanism_joint;   /* mbx_mechanism_get_joint index; -1 for a free joint */
    uint32_t q_index, v_index; /* first coordinates in the state arrays */
    uint32_t nq, nv;
} mbx_sim_joint_info;

MBX_API mbx_status mbx_sim_model_get_info(const mbx_sim_model *model, mbx_sim_model_info *out);
MBX_API mbx_status mbx_sim_model_get_joint(const mbx_sim_model *model, uint32_t index, mbx_sim_joint_info *out);
/* A joint by report name or CAD constraint id; MBX_ERROR_INVALID_ARGUMENT if
 * none or several match. */
MBX_API mbx_status mbx_sim_model_find_joint(const mbx_sim_model *model, const char *name_or_id, uint32_t *out_index);

/* The model must outlive its data objects. */
MBX_API mbx_status mbx_sim_data_create(mbx_context *context, const mbx_sim_model *model, mbx_sim_data **out_data);
MBX_API void mbx_sim_data_destroy(mbx_sim_data *data);

/* One coordinate a user fixes for mbx_sim_initialize. (Fixed layout: used in arrays.) */
typedef struct mbx_sim_fixed_value {
    uint32_t joint;   /* simulated joint index */
    uint32_t index;   /* coordinate within the joint (q: 0..nq-1, v: 0..nv-1) */
    int32_t velocity; /* 0: position, 1: velocity */
    double value;
} mbx_sim_fixed_value;

/* Consistent initialisation: time 0, the CAD assembly pose at rest, then
 * the given coordinates; the others are solved so that every loop closes
 * (positions from the CAD pose, then velocities). MBX_ERROR_INVALID_INPUT
 * names the loop when no closure satisfies the values, or the joint when a
 * value is not finite. */
MBX_API mbx_status mbx_sim_initialize(mbx_context *context, mbx_sim_data *data, const mbx_sim_fixed_value *values,
                                      uint32_t count);
/* Whole state: time, q (nq values), v (nv values); NULL arrays are skipped.
 * Setting refuses non-finite values (naming the joint) and renormalises
 * quaternions; it does not close loops (mbx_sim_initialize does). */
MBX_API mbx_status mbx_sim_get_state(const mbx_sim_data *data, double *time, double *q, double *v);
MBX_API mbx_status mbx_sim_set_state(mbx_context *context, mbx_sim_data *data, double time, const double *q,
                                     const double *v);
/* One joint's coordinates (q: its nq values, v: its nv values; NULL skips). */
MBX_API mbx_status mbx_sim_get_joint_state(const mbx_sim_data *data, uint32_t joint, double *q, double *v);
MBX_API mbx_status mbx_sim_set_joint_state(mbx_context *context, mbx_sim_data *data, uint32_t joint,
                                           const double *q, const double *v);
/* External effort per velocity coordinate (nv values; N m or N; a free
 * joint's are world force then body-frame moment), held until changed. */
MBX_API mbx_status mbx_sim_set_effort(mbx_context *context, mbx_sim_data *data, const double *effort);
/* Target of drive `drive` from now on (rad or m), e.g. a recorded
 * reference; NaN returns it to its motion program. */
MBX_API mbx_status mbx_sim_set_drive_target(mbx_context *context, mbx_sim_data *data, uint32_t drive, double target);

/* `count` steps of the model's step (fixed-step integrators), or advances by
 * count * step with error control (accurate mode). Loops are closed after
 * every step. MBX_ERROR_SIMULATION when the run diverges (the message names
 * the joint and the time); the state is then the last good one. */
MBX_API mbx_status mbx_sim_step(mbx_context *context, mbx_sim_data *data, uint32_t count);
/* Advances to `time` (a last shorter step lands on it exactly). */
MBX_API mbx_status mbx_sim_integrate(mbx_context *context, mbx_sim_data *data, double time);

/* Joint efforts (nv) that give acceleration qacc (nv) at the current state,
 * gravity and armature included, loop closures ignored (the tree's). */
MBX_API mbx_status mbx_sim_inverse_dynamics(mbx_context *context, mbx_sim_data *data, const double *qacc,
                                            double *effort);
/* Acceleration (nv) at the current state under every force and the loops. */
MBX_API mbx_status mbx_sim_forward_dynamics(mbx_context *context, mbx_sim_data *data, double *qacc);
/* Joint-space mass matrix (nv x nv, row-major), armature included. */
MBX_API mbx_status mbx_sim_mass_matrix(mbx_context *context, mbx_sim_data *data, double *matrix);

typedef struct mbx_sim_energy {
    uint32_t struct_size;
    double kinetic;  /* bodies and armature, J */
    double gravity;  /* potential, zero at the world origin */
    double spring;   /* joint springs */
    double total;
} mbx_sim_energy;
MBX_API mbx_status mbx_sim_get_energy(mbx_context *context, mbx_sim_data *data, mbx_sim_energy *out);

typedef struct mbx_sim_drive_signals {
    uint32_t struct_size;
    double target;  /* joint target, rad or m */
    double output;  /* controller output u */
    double current; /* armature current, A */
    double effort;  /* at the joint, N m or N */
} mbx_sim_drive_signals;
MBX_API mbx_status mbx_sim_get_drive_signals(const mbx_sim_data *data, uint32_t drive, mbx_sim_drive_signals *out);

typedef struct mbx_sim_stats {
    uint32_t struct_size;
    uint64_t steps;
    uint64_t evaluations;   /* forward dynamics calls */
    uint64_t mode_switches; /* accurate mode: friction stick/slip switches */
    double max_closure_residual; /* m (or rad), after projection */
} mbx_sim_stats;
MBX_API mbx_status mbx_sim_get_stats(const mbx_sim_data *data, mbx_sim_stats *out);

typedef struct mbx_sim_run_options {
    uint32_t struct_size;
    double stop_time;   /* s, after the current time */
    double output_step; /* s; a whole number of steps in fixed-step modes; 0: 0.01 */
} mbx_sim_run_options;
/* Integrates from the current state to stop_time and writes
 * <directory>/trajectory.csv (time, each joint's coordinates and rates,
 * each drive's target, output, current and effort) and simulation.json
 * (integrator, steps, evaluations, wall time, steps per second, largest
 * loop-closure residual, energy drift) as one unit: a failed or cancelled run
 * (the context's progress callback) writes nothing. The trajectory goes to
 * disk as it is computed, so memory does not grow with the run; a run whose
 * trajectory may not fit the folder's free space is refused before its first
 * step (MBX_ERROR_INVALID_ARGUMENT, both sizes named). */
MBX_API mbx_status mbx_sim_run(mbx_context *context, mbx_sim_data *data, const mbx_sim_run_options *options,
                               const char *directory);

/* ------------------------------------------------------------------------ */
/* Calibration against measured data (docs/calibration.md): replay the model  */
/* along the records, name the causes it lacks, fit them, prove the gain on   */
/* the validation records, and write the extended description file.          */
/* ------------------------------------------------------------------------ */
typedef struct mbx_calibration mbx_calibration;

typedef struct mbx_calibrate_options {
    uint32_t struct_size;
    uint32_t flags;             /* MBX_SIM_SET_GRAVITY */
    double gravity[3];          /* m/s^2, world */
    const char *experiment;     /* the experiment file (XML); required */
    /* The description file the mechanism's drives and joint dynamics came
     * from; description.xml is this file extended. NULL: none (a fresh file
     * with only the identified joints). */
    const char *description;
    /* Folder for calibration.json, calibration.html and description.xml
     * (created; written as one unit). NULL: no files, results only. */
    const char *directory;
} mbx_calibrate_options;

/* Runs the whole loop on `mechanism` with its attached drives and joint
 * dynamics (mbx_mechanism_set_mechatronics). The context's progress
 * callback sees the stages "records", "identify", "simulation fit" and
 * "replay" (a contact experiment: "records", "contact", "replay") and may
 * cancel (MBX_ERROR_CANCELLED). Bad records or experiment files fail with
 * MBX_ERROR_INVALID_INPUT naming file and line; a diverging replay with
 * MBX_ERROR_SIMULATION naming the record and time. Nothing is written on
 * failure. */
MBX_API mbx_status mbx_calibrate(mbx_context *context, const mbx_mechanism *mechanism,
                                 const mbx_calibrate_options *options, mbx_calibration **out_calibration);
MBX_API void mbx_calibration_destroy(mbx_calibration *calibration);

/* Errors in percent: 100 ||y - y_model|| / ||y|| over the fit and the
 * validation records; "identification" errors are the inverse-dynamics
 * effort errors, "simulated" ones come from replays in the experiment's
 * drive mode over its compared signals. */
typedef struct mbx_calibration_summary {
    uint32_t struct_size;
    uint32_t cause_count;
    uint32_t warning_count;
    double baseline_fit_error, baseline_validation_error;   /* identification */
    double final_fit_error, final_validation_error;
    double baseline_simulated_fit_error, baseline_simulated_validation_error;
    double final_simulated_fit_error, final_simulated_validation_error;
    double noise_level; /* % of the effort that is the records' own noise (what no model explains); NaN: none */
    double wall_time;   /* s */
    /* --- ABI 13 --- */
    /* 1: the validation error is within 1.25 times the noise level (what is
     * left is noise); 0: it stands above it; -1: the noise was not measured. */
    int32_t explained_to_noise;
    /* Sentences saying where the residual above the noise concentrates
     * (velocity reversals, high accelerations, a part of a joint's range):
     * mbx_calibration_get_residual_note. */
    uint32_t residual_note_count;
} mbx_calibration_summary;

typedef struct mbx_calibration_cause {
    uint32_t struct_size;
    const char *name;            /* coulomb_friction, viscous_friction, effort_offset, ... */
    mbx_subject_kind subject_kind; /* MBX_SUBJECT_CONSTRAINT (a joint), MBX_SUBJECT_RIGID_BODY, or
                                      MBX_SUBJECT_MODEL (mounting_tilt: the whole machine's base) */
    const char *subject_id;      /* CAD constraint id, or the body's id */
    const char *subject_name;
    const char *evidence;        /* the signature on the residual, in words and numbers */
    uint32_t parameter_count;
    int32_t written;             /* 1: held by description.xml; 0: reported only (see the JSON's reason) */
    double fit_error, validation_error;                     /* identification, after this step */
    double simulated_fit_error, simulated_validation_error; /* replays, after this step */
} mbx_calibration_cause;

typedef struct mbx_calibration_parameter {
    uint32_t struct_size;
    const char *name; /* e.g. "coulomb", "damping", "offset" */
    double value;     /* SI */
    double std_error;
} mbx_calibration_parameter;

/* Strings stay valid until the calibration is destroyed. */
MBX_API mbx_status mbx_calibration_get_summary(const mbx_calibration *calibration, mbx_calibration_summary *out);
MBX_API mbx_status mbx_calibration_get_cause(const mbx_calibration *calibration, uint32_t index,
                                             mbx_calibration_cause *out);
MBX_API mbx_status mbx_calibration_get_parameter(const mbx_calibration *calibration, uint32_t cause, uint32_t index,
                                                 mbx_calibration_parameter *out);
/* NULL past the last warning. */
MBX_API const char *mbx_calibration_get_warning(const mbx_calibration *calibration, uint32_t index);
/* (ABI 13) NULL past the last note. */
MBX_API const char *mbx_calibration_get_residual_note(const mbx_calibration *calibration, uint32_t index);

/* ------------------------------------------------------------------------ */
/* Excitation design (ABI 13; docs/calibration.md, "Excitation design"):     */
/* periodic references for the actuated joints, a Fourier series each, at    */
/* rest at both ends and within every joint's limits, along which the causes */
/* asked for are identifiable together (the smallest predicted standard      */
/* errors in the inverse-dynamics fit).                                      */
/* ------------------------------------------------------------------------ */
typedef struct mbx_excitation mbx_excitation;

/* One joint's limits for the design, SI. NaN keeps what the model has (the
 * description's or the CAD joint's range, the host's rated speed and
 * effort, a drive's limits); INFINITY: none. */
typedef struct mbx_joint_limits {
    uint32_t struct_size;
    const char *joint; /* CAD constraint id or the report's joint name */
    double lower, upper, velocity, acceleration, effort;
} mbx_joint_limits;

#define MBX_EXCITE_SET_MARGIN 2u /* mbx_excite_options.flags: use margin (else 0.1) */

typedef struct mbx_excite_options {
    uint32_t struct_size;
    uint32_t flags;            /* MBX_SIM_SET_GRAVITY, MBX_EXCITE_SET_MARGIN */
    double gravity[3];         /* m/s^2, world (turned by the description's <mounting>) */
    double period;             /* s; 0: 10 */
    uint32_t harmonics;        /* 0: 6 */
    uint32_t periods;          /* 0: 2 */
    double margin;             /* share of every limit (of the position range) left free */
    double sample_rate;        /* Hz of the records and of excitation.csv; 0: 1000 */
    double cutoff;             /* Hz of the records' filter; 0: sample_rate / 40 */
    double noise_share;        /* effort noise as a share of each effort limit; 0: 0.01 */
    double acceleration_limit; /* for every joint without one (rad/s^2 or m/s^2); 0: none */
    uint32_t evaluations;      /* of the criterion by the search; 0: 2400 */
    uint32_t seed;             /* 0: 1 */
    /* Causes to make identifiable: catalogue names (each on every subject),
     * or "cause on subject" as calibration.json writes them ("armature on
     * joint 'elbow'"). None: the default set, or calibration's. */
    const char *const *causes;
    uint32_t cause_count;
    /* A calibration.json: design for the causes it named and the groups its
     * warnings say the records could not tell apart (with `causes`, both). */
    const char *calibration;
    /* Joints to design for (ids or names); none: the driven joints, else
     * every joint with a rated speed or effort, else every tree joint of a
     * model without loops. */
    const char *const *joints;
    uint32_t joint_count;
    const mbx_joint_limits *limits; /* overrides, one per joint named */
    uint32_t limit_count;
    /* Folder for excitation.csv, experiment.xml, excitation.json and
     * excitation.html (created; written as one unit). NULL: no files. */
    const char *directory;
} mbx_excite_options;

/* Designs on `mechanism` with its attached drives and joint dynamics. The
 * context's progress callback sees the stage "excite" and may cancel. Bad
 * options, limits no motion can meet and causes no motion separates fail
 * with MBX_ERROR_INVALID_INPUT naming the joint, cause or option. */
MBX_API mbx_status mbx_excite(mbx_context *context, const mbx_mechanism *mechanism,
                              const mbx_excite_options *options, mbx_excitation **out_excitation);
MBX_API void mbx_excitation_destroy(mbx_excitation *excitation);

typedef struct mbx_excitation_summary {
    uint32_t struct_size;
    uint32_t joint_count;
    uint32_t parameter_count;
    uint32_t periods;
    uint32_t evaluations;
    double period;     /* s */
    double criterion;  /* mean log10 of the predicted standard errors */
    double wall_time;  /* s */
    /* Causes of the default set left out: this machine's efforts show them
     * not at all or only as others (mbx_excitation_get_dropped). */
    uint32_t dropped_count;
} mbx_excitation_summary;

typedef struct mbx_excitation_joint {
    uint32_t struct_size;
    const char *id, *name;
    double start;                                        /* rad or m: where the motion starts and ends */
    double lower, upper, velocity, acceleration, effort; /* the limits used (INFINITY: none) */
    const char *limit_source;                            /* where they came from, in words */
    double lowest, highest, peak_velocity, peak_acceleration, peak_effort; /* reached */
} mbx_excitation_joint;

typedef struct mbx_excitation_parameter {
    uint32_t struct_size;
    const char *name;                  /* "cause.parameter on subject" */
    double std_error;                  /* predicted along the design */
    double random_multisine_std_error; /* along a random multi-sine within the same limits */
    double measured_std_error;         /* in the given calibration.json; NaN: none */
} mbx_excitation_parameter;

/* Strings stay valid until the excitation is destroyed. */
MBX_API mbx_status mbx_excitation_get_summary(const mbx_excitation *excitation, mbx_excitation_summary *out);
MBX_API mbx_status mbx_excitation_get_joint(const mbx_excitation *excitation, uint32_t index, mbx_excitation_joint *out);
MBX_API mbx_status mbx_excitation_get_parameter(const mbx_excitation *excitation, uint32_t index,
                                                mbx_excitation_parameter *out);
/* "cause on subject"; NULL past the last. */
MBX_API const char *mbx_excitation_get_dropped(const mbx_excitation *excitation, uint32_t index);
/* The references at time t (s, clamped to the design's length): joint_count
 * positions, speeds and accelerations (any may be NULL). */
MBX_API mbx_status mbx_excitation_sample(const mbx_excitation *excitation, double t, double *q, double *qd, double *qdd);

/* ------------------------------------------------------------------------ */
/* Contact (ABI 9): collision shapes on bodies and contact materials, what    */
/* the description file's <collision> and <contact> hold (docs/contact.md).  */
/* The simulator (mbx_sim_*) runs with contact when the attached description */
/* has shapes.                                                               */
/* ------------------------------------------------------------------------ */
typedef enum mbx_collision_kind {
    MBX_COLLISION_SPHERE = 0,   /* radius */
    MBX_COLLISION_BOX = 1,      /* size: full side lengths */
    MBX_COLLISION_CYLINDER = 2, /* radius, length along the shape's z */
    MBX_COLLISION_CAPSULE = 3,  /* radius, length of the axis between the caps' centres */
    MBX_COLLISION_PLANE = 4,    /* the half-space z <= 0 of the shape's frame; world or ground only */
    MBX_COLLISION_HULL = 5      /* convex hull of the part's mesh (a body's id: one per part; "*": every moving body's parts) */
} mbx_collision_kind;

typedef struct mbx_collision_shape_desc {
    uint32_t struct_size;
    const char *body_id;  /* a rigid body's or CAD part's id, "world", or "*" (hull only) */
    const char *name;     /* NULL or "": made from the part and kind */
    int32_t kind;         /* mbx_collision_kind */
    double radius, length;
    double size[3];
    double position[3];   /* m, in the part's frame (the world's for "world") */
    double rpy[3];        /* rad: R = Rz(rpy[2]) Ry(rpy[1]) Rx(rpy[0]) */
    const char *material; /* NULL or "": "default" */
    uint32_t group, mask; /* a pair collides if each one's group meets the other's mask; both 0: 1 and all bits */
} mbx_collision_shape_desc;

typedef enum mbx_contact_normal_law {
    MBX_CONTACT_HUNT_CROSSLEY = 0, /* k d^n (1 + damping d'), damping in s/m */
    MBX_CONTACT_SPRING_DAMPER = 1, /* k d^n + damping d', damping in N s/m */
    MBX_CONTACT_SPRING = 2         /* k d^n */
} mbx_contact_normal_law;

typedef enum mbx_contact_friction_law {
    MBX_CONTACT_FRICTION_SPRING = 0,     /* anchored tangential spring: holds below mu_static N without creep */
    MBX_CONTACT_FRICTION_REGULARISED = 1 /* mu_kinetic N tanh(|v|/smoothing_speed) */
} mbx_contact_friction_law;

typedef struct mbx_contact_material_desc {
    uint32_t struct_size;
    const char *material_a, *material_b; /* both NULL or "": the default for every pair not given */
    int32_t normal_law;                  /* mbx_contact_normal_law */
    double stiffness;                    /* N/m^exponent, > 0 */
    double exponent;                     /* 0: 1.5 for Hunt-Crossley, 1 otherwise */
    double damping;                      /* unless use_restitution */
    int32_t use_restitution;             /* 1: damping solved for this restitution at impact_speed */
    double restitution, impact_speed;    /* [0, 1]; m/s (0: 1 m/s) */
    double mu_static, mu_kinetic;
    int32_t friction_law;                /* mbx_contact_friction_law */
    double friction_stiffness;           /* N/m, > 0 for the friction spring */
    double friction_damping;             /* N s/m */
    double stick_speed;                  /* m/s; 0: 1e-3 */
    double smoothing_speed;              /* m/s, regularised law; 0: 1e-3 */
} mbx_contact_material_desc;

/* Adds a collision shape (checked for form here, against the mechanism by
 * mbx_mechanism_set_mechatronics: unknown ids fail there, named). */
MBX_API mbx_status mbx_mechatronics_add_collision_shape(mbx_context *context, mbx_mechatronics *mechatronics,
                                                        const mbx_collision_shape_desc *shape);
/* Sets the contact between two materials (or the default), replacing an
 * earlier entry for the same pair. MBX_ERROR_INVALID_INPUT for bad values. */
MBX_API mbx_status mbx_mechatronics_set_contact_material(mbx_context *context, mbx_mechatronics *mechatronics,
                                                         const mbx_contact_material_desc *material);
/* Collision shapes the attached description gives the mechanism (a hull
 * request counts once per part it wraps). */
MBX_API uint32_t mbx_mechanism_collision_shape_count(const mbx_mechanism *mechanism);

/* ------------------------------------------------------------------------ */
/* View (ABI 9): one self-contained HTML page of the assembly (docs/view.md) */
/* ------------------------------------------------------------------------ */
typedef struct mbx_view_options {
    uint32_t struct_size;
    const char *trajectory; /* NULL or "": a still view; else a trajectory.csv that mbx_sim_run /
                               `mbx simulate` wrote for this mechanism, played in a loop */
    const char *title;      /* NULL or "": "model" */
} mbx_view_options;

/* Writes <directory>/view.html (directory created if missing; temporary then
 * rename): the assembly's glTF scene at its CAD pose with three.js inlined
 * from Debian's libjs-three, so it opens offline; with a trajectory, every
 * meshed body posed by forward kinematics at each sample. MBX_ERROR_IO when
 * libjs-three is missing, MBX_ERROR_INVALID_INPUT (naming file and line) for
 * a trajectory that does not fit the mechanism, or a model without meshes. */
MBX_API mbx_status mbx_mechanism_write_view(mbx_context *context, mbx_mechanism *mechanism,
                                            const mbx_view_options *options, const char *directory);

/* ------------------------------------------------------------------------ */
/* Plugin entry: one exported function returns the whole API as a table, so a */
/* host can dlopen() the plugin and dlsym() a single name.                    */
/* ------------------------------------------------------------------------ */
typedef struct mbx_api {
    uint32_t struct_size;
    uint32_t abi_version;
    /* --- version 1 --- */
    const char *(*version)(void);
    const char *(*status_name)(mbx_status);
    mbx_status (*context_create)(mbx_context **);
    void (*context_destroy)(mbx_context *);
    const char *(*context_last_error)(const mbx_context *);
    mbx_status (*context_last_error_info)(const mbx_context *, mbx_error_info *);
    mbx_status (*context_set_progress)(mbx_context *, mbx_progress_fn, void *);
    mbx_status (*translate)(mbx_context *, const mbx_host *, const mbx_translate_options *, mbx_mechanism **);
    void (*mechanism_destroy)(mbx_mechanism *);
    mbx_status (*mechanism_release_host)(mbx_mechanism *);
    mbx_status (*mechanism_get_summary)(const mbx_mechanism *, mbx_mechanism_summary *);
    mbx_status (*mechanism_get_rigid_body)(const mbx_mechanism *, uint32_t, mbx_rigid_body_info *);
    mbx_status (*mechanism_find_part)(const mbx_mechanism *, const char *, uint32_t *);
    mbx_status (*mechanism_get_joint)(const mbx_mechanism *, uint32_t, mbx_joint_info *);
    mbx_status (*mechanism_get_loop)(const mbx_mechanism *, uint32_t, mbx_loop_info *);
    mbx_status (*mechanism_get_loop_joints)(const mbx_mechanism *, uint32_t, uint32_t *, uint32_t *);
    const char *(*finding_code_name)(mbx_finding_code);
    uint32_t (*mechanism_finding_count)(const mbx_mechanism *);
    mbx_status (*mechanism_get_finding)(const mbx_mechanism *, uint32_t, mbx_finding *);
    mbx_status (*mechanism_get_shape_stats)(mbx_context *, mbx_mechanism *, uint32_t, mbx_shape_stats *);
    mbx_status (*mechanism_write_report)(mbx_context *, const mbx_mechanism *, const char *);
    /* --- version 2 --- */
    uint32_t (*abi_version_fn)(void);
    /* --- version 4 --- */
    mbx_status (*mechanism_export)(mbx_context *, mbx_mechanism *, const mbx_export_options *, const char *);
    /* --- version 5 --- */
    mbx_status (*mechatronics_create)(mbx_context *, mbx_mechatronics **);
    void (*mechatronics_destroy)(mbx_mechatronics *);
    mbx_status (*mechatronics_load_library)(mbx_context *, mbx_mechatronics *, const char *);
    mbx_status (*mechatronics_load_library_text)(mbx_context *, mbx_mechatronics *, const char *, const char *);
    mbx_status (*mechatronics_load_drives)(mbx_context *, mbx_mechatronics *, const char *);
    mbx_status (*mechatronics_add_drive)(mbx_context *, mbx_mechatronics *, const mbx_drive_desc *);
    mbx_status (*mechatronics_set_motion)(mbx_context *, mbx_mechatronics *, const char *, int32_t,
                                          const mbx_motion_point *, uint32_t, mbx_interpolation);
    uint32_t (*mechatronics_drive_count)(const mbx_mechatronics *);
    mbx_status (*mechanism_set_mechatronics)(mbx_context *, mbx_mechanism *, const mbx_mechatronics *);
    uint32_t (*mechanism_drive_count)(const mbx_mechanism *);
    mbx_status (*mechanism_get_drive)(const mbx_mechanism *, uint32_t, mbx_drive_info *);
    mbx_status (*mechanism_drive_target)(const mbx_mechanism *, uint32_t, double, double *);
    /* --- version 6 --- */
    mbx_status (*sim_model_create)(mbx_context *, const mbx_mechanism *, const mbx_sim_options *, mbx_sim_model **);
    void (*sim_model_destroy)(mbx_sim_model *);
    mbx_status (*sim_model_get_info)(const mbx_sim_model *, mbx_sim_model_info *);
    mbx_status (*sim_model_get_joint)(const mbx_sim_model *, uint32_t, mbx_sim_joint_info *);
    mbx_status (*sim_model_find_joint)(const mbx_sim_model *, const char *, uint32_t *);
    mbx_status (*sim_data_create)(mbx_context *, const mbx_sim_model *, mbx_sim_data **);
    void (*sim_data_destroy)(mbx_sim_data *);
    mbx_status (*sim_initialize)(mbx_context *, mbx_sim_data *, const mbx_sim_fixed_value *, uint32_t);
    mbx_status (*sim_get_state)(const mbx_sim_data *, double *, double *, double *);
    mbx_status (*sim_set_state)(mbx_context *, mbx_sim_data *, double, const double *, const double *);
    mbx_status (*sim_get_joint_state)(const mbx_sim_data *, uint32_t, double *, double *);
    mbx_status (*sim_set_joint_state)(mbx_context *, mbx_sim_data *, uint32_t, const double *, const double *);
    mbx_status (*sim_set_effort)(mbx_context *, mbx_sim_data *, const double *);
    mbx_status (*sim_set_drive_target)(mbx_context *, mbx_sim_data *, uint32_t, double);
    mbx_status (*sim_step)(mbx_context *, mbx_sim_data *, uint32_t);
    mbx_status (*sim_integrate)(mbx_context *, mbx_sim_data *, double);
    mbx_status (*sim_inverse_dynamics)(mbx_context *, mbx_sim_data *, const double *, double *);
    mbx_status (*sim_forward_dynamics)(mbx_context *, mbx_sim_data *, double *);
    mbx_status (*sim_mass_matrix)(mbx_context *, mbx_sim_data *, double *);
    mbx_status (*sim_get_energy)(mbx_context *, mbx_sim_data *, mbx_sim_energy *);
    mbx_status (*sim_get_drive_signals)(const mbx_sim_data *, uint32_t, mbx_sim_drive_signals *);
    mbx_status (*sim_get_stats)(const mbx_sim_data *, mbx_sim_stats *);
    mbx_status (*sim_run)(mbx_context *, mbx_sim_data *, const mbx_sim_run_options *, const char *);
    mbx_status (*mechatronics_set_joint_dynamics)(mbx_context *, mbx_mechatronics *, const mbx_joint_dynamics_desc *);
    /* --- version 8 --- */
    mbx_status (*calibrate)(mbx_context *, const mbx_mechanism *, const mbx_calibrate_options *, mbx_calibration **);
    void (*calibration_destroy)(mbx_calibration *);
    mbx_status (*calibration_get_summary)(const mbx_calibration *, mbx_calibration_summary *);
    mbx_status (*calibration_get_cause)(const mbx_calibration *, uint32_t, mbx_calibration_cause *);
    mbx_status (*calibration_get_parameter)(const mbx_calibration *, uint32_t, uint32_t, mbx_calibration_parameter *);
    const char *(*calibration_get_warning)(const mbx_calibration *, uint32_t);
    /* --- version 9 --- */
    mbx_status (*mechatronics_add_collision_shape)(mbx_context *, mbx_mechatronics *, const mbx_collision_shape_desc *);
    mbx_status (*mechatronics_set_contact_material)(mbx_context *, mbx_mechatronics *, const mbx_contact_material_desc *);
    uint32_t (*mechanism_collision_shape_count)(const mbx_mechanism *);
    mbx_status (*mechanism_write_view)(mbx_context *, mbx_mechanism *, const mbx_view_options *, const char *);
    /* --- version 10 --- */
    mbx_status (*mechatronics_set_body_correction)(mbx_context *, mbx_mechatronics *, const mbx_body_correction_desc *);
    /* --- version 11 --- */
    mbx_status (*mechatronics_load_drives_text)(mbx_context *, mbx_mechatronics *, const char *, const char *);
    /* --- version 12 --- */
    mbx_status (*mechanism_update_urdf)(mbx_context *, mbx_mechanism *, const char *, const char *);
    /* --- version 13 --- */
    const char *(*calibration_get_residual_note)(const mbx_calibration *, uint32_t);
    mbx_status (*excite)(mbx_context *, const mbx_mechanism *, const mbx_excite_options *, mbx_excitation **);
    void (*excitation_destroy)(mbx_excitation *);
    mbx_status (*excitation_get_summary)(const mbx_excitation *, mbx_excitation_summary *);
    mbx_status (*excitation_get_joint)(const mbx_excitation *, uint32_t, mbx_excitation_joint *);
    mbx_status (*excitation_get_parameter)(const mbx_excitation *, uint32_t, mbx_excitation_parameter *);
    mbx_status (*excitation_sample)(const mbx_excitation *, double, double *, double *, double *);
    const char *(*excitation_get_dropped)(const mbx_excitation *, uint32_t);
} mbx_api;

#define MBX_PLUGIN_ENTRY_NAME "mbx_plugin_api"
typedef const mbx_api *(*mbx_plugin_api_fn)(uint32_t host_abi_version);

/* Returns the API table, or NULL for host_abi_version 0. Tables only grow:
 * a host built against an older ABI reads the prefix it knows; a host built
 * against a newer one must check struct_size before calling a function that
 * lies beyond it. */
MBX_API const mbx_api *mbx_plugin_api(uint32_t host_abi_version);

#ifdef __cplusplus
}
#endif

#endif /* MBX_H */
