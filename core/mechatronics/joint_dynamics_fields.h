// The joint-dynamics coefficients every form of them carries under one name,
// in SI: the C API's mbx_joint_dynamics_desc, the description's
// JointDynamicsSpec, the resolved form (ResolvedJointDynamics) and the
// simulator's JointDynamicsT. Every copy from one form to the next is written
// once over this list, so a coefficient added here reaches the simulator from
// the C API and the description file alike (and a form that lacks it does
// not compile). What the forms hold differently is copied beside each use:
// whether limits are given (int32, bool), the direction-dependent damping and
// Coulomb level (optional in the spec, resolved to both directions, an
// `asymmetric` flag in the C struct and the simulator) and the elastic
// transmission.
#pragma once

#define MBX_JOINT_DYNAMICS_SCALARS(X)                                                                       \
    X(damping)           /* N m s/rad or N s/m; for q' > 0 only when the law is asymmetric */              \
    X(coulomb)           /* N m or N, friction effort while sliding; q' > 0 only when asymmetric */         \
    X(coulomb_velocity)  /* rad/s or m/s: regularisation speed of the fixed-step law; 0: the default */     \
    X(stribeck)          /* N m or N: static friction above the Coulomb level */                            \
    X(stribeck_velocity) /* rad/s or m/s: its decay speed */                                                \
    X(offset)            /* N m or N, any sign: constant effort the actuator supplies; acts as -offset */   \
    X(stiffness)         /* N m/rad or N/m, about rest */                                                   \
    X(rest)              /* rad or m */                                                                     \
    X(armature)          /* kg m^2 or kg, added to the joint's inertia */                                   \
    X(lower)             /* rad or m, with limited */                                                       \
    X(upper)             /* rad or m, with limited */
