// What the simulation handles hold (only sim_api.cpp uses them).
#pragma once
#include <memory>
#include <vector>

#include "sim/contact/contact_step.h"
#include "sim/integrator.h"
#include "sim/simulation.h"

struct mbx_sim_model {
    mbx::sim::Model model;
    mbx::sim::IntegratorSettings integrator;
    // Contact from the mechanism's description: no shapes, no contact.
    std::vector<mbx::sim::contact::Shape> shapes;
    mbx::sim::contact::ContactSettings contact_default;
    std::vector<mbx::sim::contact::MaterialPair> contact_pairs;
};

struct mbx_sim_data {
    const mbx_sim_model* owner;
    mbx::sim::Data data;
    // The contact world is state (the friction springs' anchors), so each
    // data has its own; it acts through data.applied_forces.
    std::unique_ptr<mbx::sim::contact::ContactWorld> contact;
    explicit mbx_sim_data(const mbx_sim_model* m) : owner(m), data(m->model) {
        if (!m->shapes.empty()) {
            contact = std::make_unique<mbx::sim::contact::ContactWorld>(m->model, m->shapes, m->contact_default,
                                                                        m->contact_pairs);
            data.applied_forces = contact.get();
        }
    }
    mbx_sim_data(const mbx_sim_data&) = delete;
    mbx_sim_data& operator=(const mbx_sim_data&) = delete;
};
