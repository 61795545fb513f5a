// A translated mechanism's dynamics as numbers two inputs can be held to:
// mass matrices and inverse dynamics at random states, through the C API.
#pragma once
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <doctest/doctest.h>
#include <mbx/mbx.h>

#include "tests/common/near.h"
#include "translation_support.h"

namespace atest {

// Mass matrices and inverse dynamics (zero acceleration and a random one)
// at random states, stacked.
inline std::vector<double> dynamics(const mbx_host* host, uint32_t expected_nv) {
    atest::Translation t(host, 0);
    REQUIRE(t.status() == MBX_OK);
    mbx_context* ctx = t.context();
    mbx_sim_model* model = nullptr;
    mbx_sim_data* data = nullptr;
    REQUIRE(mbx_sim_model_create(ctx, t.mechanism(), nullptr, &model) == MBX_OK);
    REQUIRE(mbx_sim_data_create(ctx, model, &data) == MBX_OK);
    mbx_sim_model_info info{};
    info.struct_size = sizeof info;
    REQUIRE(mbx_sim_model_get_info(model, &info) == MBX_OK);
    CHECK(info.nv == expected_nv);
    std::vector<double> out;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-2, 2);
    for (int sample = 0; sample < 5; ++sample) {
        std::vector<double> q(info.nq), v(info.nv), qacc(info.nv), M(size_t(info.nv) * info.nv), tau(info.nv);
        for (double& x : q) x = u(rng);
        for (double& x : v) x = u(rng);
        for (double& x : qacc) x = u(rng);
        REQUIRE(mbx_sim_set_state(ctx, data, 0, q.data(), v.data()) == MBX_OK);
        REQUIRE(mbx_sim_mass_matrix(ctx, data, M.data()) == MBX_OK);
        REQUIRE(mbx_sim_inverse_dynamics(ctx, data, qacc.data(), tau.data()) == MBX_OK);
        out.insert(out.end(), M.begin(), M.end());
        out.insert(out.end(), tau.begin(), tau.end());
    }
    mbx_sim_data_destroy(data);
    mbx_sim_model_destroy(model);
    return out;
}

inline void check_same(const std::vector<double>& a, const std::vector<double>& b, double tolerance) {
    REQUIRE(a.size() == b.size());
    double scale = 0;
    for (double x : b) scale = std::max(scale, std::abs(x));
    for (size_t k = 0; k < a.size(); ++k) {
        CAPTURE(k);
        CHECK(a[k] == mbx_test::within(b[k], tolerance * scale, "relative to the largest entry"));
    }
}

}  // namespace atest
