// The object library from text, then what consumers ask of it: every object
// by ID and the SI value of each of its parameters.
#include "fuzz_common.h"
#include "core/mechatronics/object_library.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    mbx::ObjectLibrary library;
    library.load_text(fuzz_text(data, size), std::string(kFuzzDir) + "/library.xml");
    for (const mbx::LibraryError& e : library.errors()) (void)e.text();
    for (const mbx::LibraryFolder& folder : library.folders())
        for (const mbx::LibraryClass& cls : folder.classes)
            for (const mbx::LibraryObject& object : cls.objects) {
                const mbx::ObjectLibrary::Found found = library.find(object.id);
                if (!found.object) __builtin_trap();  // a loaded object must be found by its ID
                for (const auto& p : cls.parameters) (void)library.value_in_si(found, p.name);
            }
    return 0;
}
