#include "host_adapters/inputs/input_formats.h"

#include <algorithm>
#include <cctype>
#include <fstream>

#include "host_adapters/common/file_error.h"
#include "host_adapters/pmxml_vrml/file_adapter.h"
#include "host_adapters/simscape/simscape_adapter.h"
#include "host_adapters/simscape/simscape_reader.h"
#include "host_adapters/urdf/urdf_adapter.h"
#include "host_adapters/urdf/urdf_reader.h"
#include "host_adapters/common/text.h"

namespace mbx_files {

namespace {

std::unique_ptr<FileInput> open_pmxml(const std::string& path, const FileInputOptions& options) {
    return FileAdapter::open(path, options);
}

std::unique_ptr<FileInput> open_simscape(const std::string& path, const FileInputOptions& options) {
    return SimscapeAdapter::open(path, options);
}

std::unique_ptr<FileInput> open_urdf(const std::string& path, const FileInputOptions& options) {
    return UrdfAdapter::open(path, options);
}

std::string lower_extension(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    const size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    return lower_case(path.substr(dot));
}

// The first element's name in an XML file, its namespace prefix dropped; ""
// when the file cannot be read or does not start like XML. Only the head is
// read: the declaration, comments, processing instructions and a DOCTYPE
// come before the root in any export.
std::string xml_root_element(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return "";
    std::string head(16384, '\0');
    in.read(&head[0], std::streamsize(head.size()));
    head.resize(size_t(in.gcount()));
    size_t i = head.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;  // UTF-8 byte order mark
    while (i < head.size()) {
        while (i < head.size() && std::isspace(static_cast<unsigned char>(head[i]))) ++i;
        if (i >= head.size() || head[i] != '<') return "";
        if (head.compare(i, 4, "<!--") == 0) {
            const size_t end = head.find("-->", i + 4);
            if (end == std::string::npos) return "";
            i = end + 3;
        } else if (head.compare(i, 2, "<?") == 0) {
            const size_t end = head.find("?>", i + 2);
            if (end == std::string::npos) return "";
            i = end + 2;
        } else if (head.compare(i, 2, "<!") == 0) {
            // DOCTYPE, possibly with an internal subset in brackets.
            int depth = 0;
            size_t k = i + 2;
            for (; k < head.size(); ++k) {
                if (head[k] == '[') ++depth;
                else if (head[k] == ']') --depth;
                else if (head[k] == '>' && depth <= 0) break;
            }
            if (k >= head.size()) return "";
            i = k + 1;
        } else {
            size_t k = i + 1;
            while (k < head.size() && !std::isspace(static_cast<unsigned char>(head[k])) && head[k] != '>' &&
                   head[k] != '/')
                ++k;
            std::string name = head.substr(i + 1, k - i - 1);
            const size_t colon = name.find(':');
            if (colon != std::string::npos) name = name.substr(colon + 1);
            return name;
        }
    }
    return "";
}

// "*.xml, *.foo": a format's extensions as help texts and errors name them.
std::string extension_list(const InputFormat& f) {
    std::string out;
    for (const std::string& ext : f.extensions) out += (out.empty() ? "*" : ", *") + ext;
    return out;
}

}  // namespace

const std::vector<InputFormat>& input_formats() {
    static const std::vector<InputFormat> formats = {
        {"pmxml",
         "SimMechanics first-generation Physical Modeling XML; shapes from the mesh files it names or a VRML97 scene",
         {".xml"},
         {"PhysicalModelingXMLFile"},
         true,
         open_pmxml},
        {"simscape",
         "Simscape Multibody second-generation import XML (Onshape, SolidWorks, Creo, Inventor), a STEP file per part",
         {".xml"},
         {kSimscapeRootElement, kSimMechanicsImportRootElement},
         false,
         open_simscape},
        {"urdf",
         "URDF robot description (ROS); meshes relative to it, absolute or package:// (--package-path)",
         {".urdf"},
         {kUrdfRootElement},
         false,
         open_urdf},
    };
    return formats;
}

const InputFormat* input_format_of(const std::string& path) {
    const std::string root = xml_root_element(path);
    if (!root.empty())
        for (const InputFormat& f : input_formats())
            if (std::find(f.root_elements.begin(), f.root_elements.end(), root) != f.root_elements.end()) return &f;
    const std::string ext = lower_extension(path);
    if (ext.empty()) return nullptr;
    for (const InputFormat& f : input_formats())
        if (std::find(f.extensions.begin(), f.extensions.end(), ext) != f.extensions.end()) return &f;
    return nullptr;
}

std::unique_ptr<FileInput> open_input(const std::string& path, const FileInputOptions& options) {
    const InputFormat* format = input_format_of(path);
    if (!format) {
        std::string known;
        for (const InputFormat& f : input_formats()) known += (known.empty() ? "" : ", ") + extension_list(f);
        throw FileError(path, 0, "not a file format mbx reads (" + known + ")");
    }
    return format->open(path, options);
}

std::string input_formats_help() {
    std::string out;
    for (const InputFormat& f : input_formats()) {
        out += std::string("  ") + f.name + "  " + f.description + " (" + extension_list(f) + ")\n";
    }
    return out;
}

}  // namespace mbx_files
