#include "core/mechatronics/drive_quantities.h"

#include <cmath>

namespace mbx {

namespace {

bool need(const ObjectLibrary& lib, const ObjectLibrary::Found& f, const char* name, double& out,
          std::string& error) {
    const std::optional<double> v = lib.value_in_si(f, name);
    if (!v) {
        error = "class '" + f.cls->name + "' gives no numeric '" + name + "'";
        return false;
    }
    out = *v;
    return true;
}

}  // namespace

std::optional<DcMotorConstants> dc_motor_constants(const ObjectLibrary& lib, const ObjectLibrary::Found& motor,
                                                   std::string& error) {
    if (!motor.cls || motor.cls->kind != "dc_motor") {
        error = "not a dc_motor object";
        return std::nullopt;
    }
    double va = 0, ia = 0, w = 0, ra = 0;
    DcMotorConstants c;
    if (!need(lib, motor, "J_Rotor", c.rotor_inertia, error) || !need(lib, motor, "VaNominal", va, error) ||
        !need(lib, motor, "IaNominal", ia, error) || !need(lib, motor, "rpmNominal", w, error) ||
        !need(lib, motor, "Ra", ra, error))
        return std::nullopt;
    c.ratio = lib.value_in_si(motor, "Ratio").value_or(1.0);
    const double emf = va - ra * ia;
    if (!(w > 0) || !(emf > 0) || !(ra > 0)) {
        error = "nominal values give no positive back-EMF constant (Va - Ra Ia must be > 0 at a speed > 0)";
        return std::nullopt;
    }
    c.torque_constant = emf / w;
    c.stall_torque = c.torque_constant * va / ra;
    c.no_load_speed = va / c.torque_constant;
    c.reflected_inertia = c.rotor_inertia * c.ratio * c.ratio;
    return c;
}

std::optional<TransmissionConstants> transmission_constants(const ObjectLibrary& lib,
                                                            const ObjectLibrary::Found& t, std::string& error) {
    if (!t.cls || (t.cls->kind != "gearbox" && t.cls->kind != "ball_screw")) {
        error = "not a gearbox or ball_screw object";
        return std::nullopt;
    }
    TransmissionConstants c;
    if (!need(lib, t, "efficiency", c.efficiency, error) || !need(lib, t, "J", c.inertia, error)) return std::nullopt;
    if (t.cls->kind == "gearbox") {
        if (!need(lib, t, "ratio", c.ratio, error)) return std::nullopt;
    } else {
        double lead = 0;
        if (!need(lib, t, "lead", lead, error)) return std::nullopt;
        if (!(lead > 0)) {
            error = "lead must be positive";
            return std::nullopt;
        }
        c.ratio = 2 * M_PI / lead;
        c.linear = true;
    }
    c.reflected_inertia = c.inertia * c.ratio * c.ratio;
    return c;
}

}  // namespace mbx
