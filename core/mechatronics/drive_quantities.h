// What a library object means for a joint it drives, derived from its class
// parameters (thesis section 2.8.1 lists the nominal values; the constants
// follow from the DC machine's steady state U = R I + k w, tau = k I).
#pragma once
#include <optional>
#include <string>

#include "core/mechatronics/object_library.h"

namespace mbx {

struct DcMotorConstants {
    double torque_constant = 0;   // k, N m/A (= back-EMF constant, V s/rad)
    double stall_torque = 0;      // k Va / Ra, N m, motor shaft
    double no_load_speed = 0;     // Va / k, rad/s, motor shaft
    double rotor_inertia = 0;     // kg m^2
    double ratio = 1;             // built-in gear (Ratio), motor turns per output turn
    double reflected_inertia = 0; // J N^2 at the output, kg m^2
};

// For class kind "dc_motor": parameters J_Rotor, VaNominal, IaNominal,
// rpmNominal, Ra (La and Ratio optional). `error` says what is missing or
// physically impossible (a back-EMF that is not positive).
std::optional<DcMotorConstants> dc_motor_constants(const ObjectLibrary& lib, const ObjectLibrary::Found& motor,
                                                   std::string& error);

struct TransmissionConstants {
    double ratio = 1;              // gearbox: input turns per output turn; screw: rad per metre (2 pi / lead)
    double efficiency = 1;
    double inertia = 0;            // own inertia at its input, kg m^2
    double reflected_inertia = 0;  // at the output: J N^2 (kg m^2), or kg for a screw
    bool linear = false;           // ball screw: output is a translation
};

// For kinds "gearbox" (ratio, efficiency, J) and "ball_screw" (lead,
// efficiency, J).
std::optional<TransmissionConstants> transmission_constants(const ObjectLibrary& lib,
                                                            const ObjectLibrary::Found& transmission,
                                                            std::string& error);

}  // namespace mbx
