// The VRML97 reader from text. Default limits, as the file adapter uses them.
#include "fuzz_common.h"
#include "host_adapters/pmxml_vrml/vrml_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const mbx_files::VrmlScene scene =
            mbx_files::read_vrml_text(fuzz_text(data, size), std::string(kFuzzDir) + "/scene.wrl");
        (void)scene;
    } catch (const mbx_files::VrmlError&) {
    }
    return 0;
}
