// Reads first-generation SimMechanics / Simscape Multibody "Physical Modeling
// XML" (root <PhysicalModelingXMLFile>, container <SimMechanics> or
// <SimscapeMultibody>) as described in shared/data/pmxml/FORMAT_NOTES.md:
// string values in literal quotes, orientation matrices column-major, every
// pose absolute in WORLD, units per quantity, frame refs global to the file.
//
// Anything the model cannot be built from (malformed XML, a missing
// geometry-critical element, an unreadable number or unit, a duplicate or
// dangling frame ref, a frame or axis given relative to anything but WORLD,
// an unknown primitive) throws FileError with the line of the element at
// fault. Everything else is optional, as exporters differ.
#pragma once
#include <string>
#include <string_view>

#include "host_adapters/common/file_error.h"
#include "pmxml_model.h"

namespace mbx_files {

// How a file is parsed: by parts (pmxml_outline.h: no DOM of the whole file,
// each part as a small fragment) wherever the outline takes the file, else as
// one DOM. Both give the same model, the same diagnostics and the same
// errors; `whole_dom` forces the second (tests compare the two).
enum class PmxmlParse { automatic, by_parts, whole_dom };

// Reads the file at `path`; messages name `path`. `used`, if given, is told
// which way the file was parsed.
PmxmlModel read_pmxml(const std::string& path, PmxmlParse how = PmxmlParse::automatic, PmxmlParse* used = nullptr);

// Parses XML text; messages name `file`.
PmxmlModel parse_pmxml(std::string_view text, const std::string& file, PmxmlParse how = PmxmlParse::automatic,
                       PmxmlParse* used = nullptr);

}  // namespace mbx_files
