// The state of the drives in the loop (sim/drive_loop.h): one controller
// per model drive with its held output, and what each drive did last.
#pragma once
#include <cmath>
#include <vector>

#include "core/mechatronics/drive_controller.h"

namespace mbx::sim {

// What one drive did at the last evaluation (for trajectories and the C API).
struct DriveSignals {
    double target = 0;   // joint target (rad or m)
    double output = 0;   // controller output u (V in voltage mode, amplifier units otherwise)
    double current = 0;  // armature current (A)
    double effort = 0;   // at the joint (N m or N)
};

// Controllers and their signals, one per model drive.
struct DriveLoop {
    std::vector<DriveController> controllers;
    std::vector<DriveSignals> signals;
    // A target given from outside per drive (a recorded reference): NaN
    // means the drive's own motion profile.
    std::vector<double> target_override;
    // A signal added to each controller's output after its limit and delay
    // (an injected test signal, a recorded disturbance), in output units.
    std::vector<double> output_add;

    DriveLoop() = default;
    explicit DriveLoop(const std::vector<Drive>& drives) {
        controllers.reserve(drives.size());
        for (const Drive& d : drives) {
            ControllerSpec c = d.spec.controller;
            c.output_limit = d.output_limit;  // the resolved bound (the amplifier's when unset)
            controllers.emplace_back(c);
        }
        signals.assign(drives.size(), {});
        target_override.assign(drives.size(), NAN);
        output_add.assign(drives.size(), 0.0);
    }
    void reset() {
        for (DriveController& c : controllers) c.reset();
        for (DriveSignals& s : signals) s = {};
    }
};

}  // namespace mbx::sim
