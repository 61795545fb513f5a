// URDF as its adapter reads it: parse, build the host assembly (the tree,
// world poses, every joint type, a floating base every other input), and
// translate it through the C API (what `mbx translate robot.urdf` does,
// minus the mesh files), so values the reader lets through meet the
// translator too; and the same bytes as a cut-joint file.
#include <mbx/mbx.h>

#include "fuzz_common.h"
#include "host_adapters/memory/memory_host.h"
#include "host_adapters/urdf/urdf_assembly.h"
#include "host_adapters/urdf/urdf_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text = fuzz_text(data, size);
    // The same bytes as a cut-joint file (the JSON mbx's URDF export writes beside a looped mechanism).
    try {
        mbx_files::parse_cut_joints(text, std::string(kFuzzDir) + "/fuzz.cut_joints.json");
    } catch (const mbx_files::FileError&) {
    }
    mbx_files::UrdfAssembly built;
    try {
        const mbx_files::UrdfModel model = mbx_files::parse_urdf(text, std::string(kFuzzDir) + "/fuzz.urdf");
        mbx_files::UrdfAssemblyOptions options;
        options.floating_base = size % 2 == 1;
        built = mbx_files::to_assembly(model, options);
    } catch (const mbx_files::FileError&) {
        return 0;  // the documented rejection
    }
    mbx_memory::Host host(built.assembly);
    mbx_context* context = nullptr;
    if (mbx_context_create(&context) != MBX_OK) __builtin_trap();
    mbx_translate_options options{};
    options.struct_size = sizeof options;
    mbx_mechanism* mechanism = nullptr;
    if (mbx_translate(context, host.table(), &options, &mechanism) == MBX_OK) {
        mbx_mechanism_summary summary{};
        summary.struct_size = sizeof summary;
        mbx_mechanism_get_summary(mechanism, &summary);
        mbx_mechanism_destroy(mechanism);
    } else if (mbx_context_last_error(context) == nullptr) {
        __builtin_trap();  // a failure must say why
    }
    mbx_context_destroy(context);
    return 0;
}
