// The STEP tessellator from text: whatever the reader accepts is placed and
// meshed (at a coarse tolerance, so that an input is a few milliseconds)
// without a crash or a hang, and what comes out holds together: every
// triangle's corners inside its mesh's points, every placement's solid inside
// the B-rep, every point of a mesh finite.
#include <cmath>

#include "fuzz_common.h"
#include "host_adapters/step/assembly.h"
#include "host_adapters/step/tessellate.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const mbx_step::File f = mbx_step::read_part21(fuzz_text(data, size), "fuzz.stp");
        const mbx_step::Brep b = mbx_step::read_breps(f);
        const mbx_step::Assembly placed = mbx_step::place_solids(f, b);
        for (const mbx_step::PlacedSolid& p : placed.solids)
            if (p.solid >= b.solids.size()) __builtin_trap();
        mbx_step::Tolerance coarse;
        coarse.relative_chord = 1e-3;
        coarse.angle = 20 * M_PI / 180;
        for (const mbx_step::SolidMesh& m : mbx_step::tessellate(b, coarse)) {
            for (const auto& t : m.mesh.triangles)
                for (uint32_t corner : t)
                    if (corner >= m.mesh.points.size()) __builtin_trap();
            for (const auto& t : m.mesh.triangles)
                for (uint32_t corner : t)
                    if (!m.mesh.points[corner].allFinite()) __builtin_trap();
        }
    } catch (const mbx_step::ReadError&) {
    }
    return 0;
}
