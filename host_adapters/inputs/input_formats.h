// The one table of input file formats. The command-line tool, the file host's
// C face (libmbx_files) and so the Python package pick the adapter for an
// input here, by the file's root element when it is XML and by its extension
// otherwise. A new format is one entry in input_formats.cpp plus its own
// adapter folder beside pmxml_vrml/.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "host_adapters/common/file_input.h"

namespace mbx_files {

struct InputFormat {
    const char* name;         // short, stable: "pmxml"
    const char* description;  // one line for help texts
    // Lower-case, with the dot. A file with one of these whose content names
    // no other format (below) is this format's.
    std::vector<std::string> extensions;
    // XML root element names (without a namespace prefix) that identify this
    // format whatever the file's extension; empty for formats that are not XML.
    std::vector<std::string> root_elements;
    bool takes_scene;  // whether FileInputOptions::shapes_path means anything to it
    // Reads the input; throws FileError (file, line, message) for an unusable file.
    std::unique_ptr<FileInput> (*open)(const std::string& path, const FileInputOptions& options);
};

const std::vector<InputFormat>& input_formats();

// The format of `path`: the one whose root element the file's XML starts with,
// else the one its extension belongs to; null when neither (a name that is no
// file, or a file of no known format).
const InputFormat* input_format_of(const std::string& path);

// Opens `path` with its format's adapter. Throws FileError when no format
// takes it (naming the formats that exist) or the adapter refuses the file.
std::unique_ptr<FileInput> open_input(const std::string& path, const FileInputOptions& options = {});

// "  pmxml  <description> (*.xml)" lines, one per format, for help texts.
std::string input_formats_help();

}  // namespace mbx_files
