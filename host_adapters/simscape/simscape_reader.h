// Reads a Simscape Multibody second-generation import file (the XML that
// Onshape, SolidWorks, Creo and Inventor export with one STEP file per part)
// into a SimscapeModel. Throws FileError (file, line, message) where the file
// cannot describe an assembly; what it can step over (an unknown joint, a
// colour it cannot read) becomes a diagnostic of the model.
#pragma once
#include <string>
#include <string_view>

#include "host_adapters/common/file_error.h"
#include "simscape_model.h"

namespace mbx_files {

// The root elements (namespace prefix dropped) this reader takes: version
// 2.0 (Onshape, Link 5 and later) and its predecessor, version 1.0 of
// SimMechanics Link 4.x.
inline constexpr const char* kSimscapeRootElement = "SimscapeMultibodyImportXML";
inline constexpr const char* kSimMechanicsImportRootElement = "SimMechanicsImportXML";

SimscapeModel read_simscape(const std::string& path);
// The same from text in memory (`file` names it in messages).
SimscapeModel parse_simscape(std::string_view text, const std::string& file);

}  // namespace mbx_files
