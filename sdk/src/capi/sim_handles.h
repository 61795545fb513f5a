// What the simulation handles hold (only sim_api.cpp uses them).
#pragma once
#include "sim/integrator.h"
#include "sim/simulation.h"

struct mbx_sim_model {
    mbx::sim::Model model;
    mbx::sim::IntegratorSettings integrator;
};

struct mbx_sim_data {
    const mbx_sim_model* owner;
    mbx::sim::Data data;
    explicit mbx_sim_data(const mbx_sim_model* m) : owner(m), data(m->model) {}
};
