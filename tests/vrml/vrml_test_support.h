// Helpers of the VRML reader tests: a scratch directory for the files a test
// writes, mesh measures, and checks of VrmlError locations.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "host_adapters/pmxml_vrml/vrml_reader.h"
#include "host_adapters/common/vrml_scene.h"

namespace vrml_test {

// A fresh directory under the system temp directory, removed with its
// content when the object goes.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::string& path() const { return path_; }
    // Writes `text` to `relative` (folders created) and returns the full path.
    std::string write(const std::string& relative, const std::string& text) const;

private:
    std::string path_;
};

// Signed volume by the tetrahedra to the origin: exact for a closed mesh,
// positive when it winds counter-clockwise seen from outside.
double signed_volume(const mbx_files::VrmlMesh& mesh);

// Every directed edge is matched by exactly one opposite edge: the mesh is
// closed and consistently oriented.
bool is_closed(const mbx_files::VrmlMesh& mesh);

// Index of the first node with DEF name `name`, -1 if none.
int find_node(const mbx_files::VrmlScene& scene, const std::string& name);

// Runs `f`, which must throw VrmlError at a file ending in `file_suffix`
// and `line`, with `fragment` in the message ("file:line: ..." checked too).
void check_error(const std::function<void()>& f, const std::string& file_suffix, int line, const std::string& fragment);

// Writes `text` as `name` into a fresh scratch directory and reads it with
// read_vrml.
mbx_files::VrmlScene read_written(const std::string& text, const std::string& name,
                                  const mbx_files::VrmlLimits& limits = {});

// "#VRML V2.0 utf8\n" + body.
std::string vrml(const std::string& body);

}  // namespace vrml_test
