// The STEP Part 21 reader from text: it refuses or reads, and what it reads
// holds together (every reference resolved into the table or marked dangling,
// every list inside the value array).
#include "fuzz_common.h"
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
    } catch (const mbx_step::ReadError&) {
    }
    return 0;
}
