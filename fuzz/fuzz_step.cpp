// The STEP Part 21 reader from text: it refuses or reads, and what it reads
// holds together (every reference resolved into the table or marked dangling,
// every list inside the value array); then the B-rep reader over that table,
// whose indices must stay inside its arrays.
#include "fuzz_common.h"
#include "host_adapters/step/brep.h"
#include "host_adapters/step/part21.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const mbx_step::File f = mbx_step::read_part21(fuzz_text(data, size), "fuzz.stp");
        for (const mbx_step::Value& v : f.values) {
            if (v.kind == mbx_step::Kind::Reference && v.a != mbx_step::kUnresolved && v.a >= f.instances.size())
                __builtin_trap();
            if (v.kind == mbx_step::Kind::List && v.a + v.count > f.values.size()) __builtin_trap();
            if ((v.kind == mbx_step::Kind::String || v.kind == mbx_step::Kind::Enumeration) &&
                v.a + v.count > f.text_pool.size())
                __builtin_trap();
        }
        for (const mbx_step::Instance& in : f.instances)
            if (in.first_record + in.record_count > f.records.size() || f.find(in.id) == nullptr) __builtin_trap();
        const mbx_step::Brep b = mbx_step::read_breps(f);
        for (const mbx_step::Edge& e : b.edges)
            if (e.start >= b.vertices.size() || e.end >= b.vertices.size()) __builtin_trap();
        for (const mbx_step::Face& face : b.faces)
            for (const mbx_step::Loop& l : face.bounds)
                for (const mbx_step::OrientedEdge& oe : l.edges)
                    if (oe.edge >= b.edges.size()) __builtin_trap();
        for (const mbx_step::Solid& s : b.solids)
            for (const mbx_step::Shell& sh : s.shells)
                for (uint32_t fi : sh.faces)
                    if (fi >= b.faces.size()) __builtin_trap();
    } catch (const mbx_step::ReadError&) {
    }
    return 0;
}
