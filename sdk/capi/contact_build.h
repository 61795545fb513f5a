// The simulator's contact world from a mechanism's resolved description:
// shapes in the simulation bodies' frames (hulls computed from the parts'
// meshes, which the host gives), and per material pair the laws, with
// dampings solved from restitutions.
#pragma once
#include "sdk/capi/sim_handles.h"

struct mbx_mechanism;

namespace mbx {

// Fills model's shapes and contact settings (leaves them empty without
// shapes). Throws mbx::Error naming the shape or part on failure.
void build_contact(const mbx_mechanism& mechanism, mbx_sim_model& model);

// The simulator's settings for one description entry; `mass` is the mass a
// restitution is solved for (only the spring-damper law depends on it).
sim::contact::ContactSettings contact_settings(const ContactMaterialSpec& spec, double mass);

}  // namespace mbx
