// A user's own URDF with a model's joint dynamics and inertials written into
// it (docs/urdf.md, "Writing a calibrated URDF"): what `mbx calibrate
// --write-urdf` and mbx_mechanism_update_urdf produce. Only the values that
// differ from the file change; every other byte stays as the user wrote it.
#pragma once
#include <string>
#include <string_view>

#include "export/common/export_model.h"

namespace mbx {

struct UrdfUpdate {
    std::string text;
    int joints_changed = 0;  // <dynamics> written
    int links_changed = 0;   // <inertial> written
};

// `model`: the mechanism translated from `urdf` (links are its CAD parts,
// joints its constraints, by name) with the description that is to go into
// the file attached (body mass corrections applied, joint dynamics
// resolved). Per tree joint with joint dynamics: <dynamics damping
// friction> gets the law's symmetric damping and Coulomb level (a drive's
// back-EMF damping stays the drive's); what URDF cannot hold (armature,
// spring, asymmetry, Stribeck peak, constant effort) is a note on the model.
// Per rigid body whose inertia differs from its links' as the file gives
// them: each massive link's <inertial> gets its share (mass scaled alike,
// centre of mass moved alike, a change of the inertia tensor to the
// heaviest link), in the inertial's own axes. Throws mbx::Error naming the
// file and line when `urdf` is not the file the mechanism was read from (a
// link or joint missing, a link's mass differing) or a link's share would
// not be a physical inertia.
UrdfUpdate update_urdf(ExportModel& model, std::string_view urdf, const std::string& file);

}  // namespace mbx
