#!/usr/bin/env python3
"""After the quickstart: the five-axis arm from Python.

Translates the five-axis arm sample (PMXML + VRML), attaches its motors,
controllers and motion program, simulates the whole program and plots how
one joint tracks its target, to a PNG.

    python3 samples/python/arm_tracking.py                     # writes arm_tracking.png
    python3 samples/python/arm_tracking.py --joint elbow -o elbow.png

From a build tree (not installed), point the package at it first:

    export PYTHONPATH=$PWD/python MBX_LIBRARY=$PWD/build/lib
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # a file, no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mbx  # noqa: E402

SAMPLES = pathlib.Path(__file__).resolve().parent.parent


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--joint", default="waist",
                        help="drive to plot: waist, shoulder, elbow, wrist_pitch, wrist_roll")
    parser.add_argument("--stop-time", type=float, default=12.6, help="s; the motion program ends at 12.6 s")
    parser.add_argument("-o", "--output", default="arm_tracking.png", help="PNG to write")
    args = parser.parse_args()

    arm = mbx.translate(SAMPLES / "five_axis_arm" / "five_axis_arm.xml",
                        shapes=SAMPLES / "five_axis_arm" / "five_axis_arm_a.wrl")
    s = arm.summary
    print(f"translated: {s.rigid_body_count} bodies, {s.joint_count} joints, {s.dof} DoF, "
          f"{len(arm.findings)} findings")
    arm.attach_drives(SAMPLES / "mechatronics" / "five_axis_arm_drives.xml")

    sim = arm.simulation(integrator="rk4", step=1e-3)
    sim.initialize()  # CAD pose, at rest
    traj = sim.record(stop_time=args.stop_time, output_step=0.005)

    drive = traj.drive(args.joint)  # raises ValueError for an unknown drive name
    mechanism_joint = arm.drives[drive].joint
    joint = next(j for j in sim.joints if j.mechanism_joint == mechanism_joint)
    q = np.degrees(traj.q[:, joint.q_index])
    target = np.degrees(traj.drive_target[:, drive])
    error = q - target
    print(f"{args.joint}: largest tracking error {np.max(np.abs(error)):.3f} deg, "
          f"final {q[-1]:.3f} deg (target {target[-1]:.3f} deg)")

    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    top.plot(traj.time, target, "--", label="target")
    top.plot(traj.time, q, label="simulated")
    top.set_ylabel(f"{args.joint} angle (deg)")
    top.legend()
    top.set_title(f"five-axis arm: {args.joint} ({joint.name}) following its motion program")
    bottom.plot(traj.time, error, color="C3", label="tracking error (deg)")
    ax2 = bottom.twinx()
    ax2.plot(traj.time, traj.drive_current[:, drive], color="C2", alpha=0.6, label="armature current (A)")
    bottom.set_xlabel("time (s)")
    bottom.set_ylabel("error (deg)")
    ax2.set_ylabel("current (A)")
    fig.tight_layout()
    fig.savefig(args.output, dpi=100)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
