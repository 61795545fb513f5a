// STEP files read by mbx's Part 21 reader against OpenCASCADE's
// STEPControl_Reader::ReadFile (its Part 21 parse into the StepData model,
// before any shape is built), on the real files of ../shared/data/step and
// Debian's occt-misc and gmsh-doc: milliseconds, MB/s and the ratio, with a
// bare pass over the bytes (counting ';') as the floor. Then the whole way
// from file to triangles at one chord and angle tolerance: mbx's read, B-rep,
// placement and tessellation against OpenCASCADE's read, transfer and
// BRepMesh_IncrementalMesh, with the triangle counts each makes; and the cost
// of files of 1 to 256 solids, per solid.
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "host_adapters/step/assembly.h"
#include "host_adapters/step/part21.h"
#include "host_adapters/step/tessellate.h"
#include "tests/common/step_solids.h"

namespace {

double best_ms(int runs, const std::function<void()>& f) {
    double best = 1e300;
    for (int k = 0; k < runs; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

int main(int argc, char** argv) {
    const std::string shared = argc > 1 ? argv[1] : MBX_SHARED_DATA;
    std::vector<std::string> files = {
        shared + "/step/dfki_double_pendulum/lever_200.STEP",
        shared + "/step/dfki_double_pendulum/double_pendulum.STEP",
        shared + "/step/nist_ctc_02/nist_ctc_02_asme1_ap242-1.stp",
        "/usr/share/opencascade/data/step/screw.step",
        "/usr/share/opencascade/data/step/linkrods.step",
    };
    // OpenCASCADE reports each file it reads on its messenger: silenced, so the
    // table stays readable and the printing is not timed.
    Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_Printer));
    std::printf("%-34s %9s %9s %8s %8s %9s %9s %7s\n", "file", "MB", "instances", "bare ms", "mbx ms", "mbx MB/s",
                "OCCT ms", "ratio");
    for (const std::string& path : files) {
        const std::string text = read_text(path);
        if (text.empty()) {
            std::printf("%-34s (missing)\n", path.substr(path.rfind('/') + 1).c_str());
            continue;
        }
        const double mb = double(text.size()) / 1e6;
        size_t statements = 0;
        const double bare = best_ms(5, [&] {
            statements = 0;
            for (const char* p = text.data(); (p = static_cast<const char*>(std::memchr(p, ';', size_t(text.data() + text.size() - p))));
                 ++p)
                ++statements;
        });
        size_t instances = 0;
        const double ours = best_ms(5, [&] { instances = mbx_step::read_part21_file(path).instances.size(); });
        const double occt = best_ms(3, [&] {
            STEPControl_Reader reader;
            if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) std::printf("OCCT could not read %s\n", path.c_str());
        });
        std::printf("%-34s %9.2f %9zu %8.2f %8.2f %9.0f %9.1f %6.1fx\n", path.substr(path.rfind('/') + 1).c_str(), mb,
                    instances, bare, ours, mb / (ours / 1e3), occt, occt / ours);
        (void)statements;
    }
    // File to triangles at one tolerance for both: a chord of 1e-4 of the
    // file's extent, 5 degrees (at mbx's default, 1e-5 and 1 degree,
    // OpenCASCADE's mesher takes 11 s on lever_200 alone).
    std::printf("\n%-34s %9s %9s %10s %9s %10s %10s %7s\n", "file to triangles", "chord mm", "mbx ms", "mbx tris",
                "Mtri/s", "OCCT ms", "OCCT tris", "ratio");
    Interface_Static::SetCVal("xstep.cascade.unit", "M");
    for (const std::string& path : files) {
        if (read_text(path).empty()) continue;
        Eigen::AlignedBox3d box;
        {
            const mbx_step::Brep b = mbx_step::read_breps(mbx_step::read_part21_file(path));
            for (const mbx_step::Vertex& v : b.vertices) box.extend(v.point);
        }
        const double chord = 1e-4 * box.diagonal().norm(), angle = 5 * M_PI / 180;
        size_t ours_triangles = 0, occt_triangles = 0;
        const double ours = best_ms(2, [&] {
            const mbx_step::File f = mbx_step::read_part21_file(path);
            const mbx_step::Brep b = mbx_step::read_breps(f);
            const mbx_step::Assembly placed = mbx_step::place_solids(f, b);
            ours_triangles = 0;
            const std::vector<mbx_step::SolidMesh> meshes = mbx_step::tessellate(b, mbx_step::Tolerance::absolute(chord, angle));
            for (const mbx_step::SolidMesh& m : meshes) ours_triangles += m.mesh.triangles.size();
            (void)placed;
        });
        const double occt = best_ms(2, [&] {
            STEPControl_Reader reader;
            reader.ReadFile(path.c_str());
            reader.TransferRoots();
            const TopoDS_Shape shape = reader.OneShape();
            BRepMesh_IncrementalMesh mesh(shape, chord, Standard_False, angle, Standard_False);
            occt_triangles = 0;
            TopLoc_Location where;
            for (TopExp_Explorer f(shape, TopAbs_FACE); f.More(); f.Next()) {
                const Handle(Poly_Triangulation) t = BRep_Tool::Triangulation(TopoDS::Face(f.Current()), where);
                if (!t.IsNull()) occt_triangles += size_t(t->NbTriangles());
            }
        });
        std::printf("%-34s %9.4f %9.1f %10zu %9.2f %10.1f %10zu %6.1fx\n", path.substr(path.rfind('/') + 1).c_str(),
                    chord * 1e3, ours, ours_triangles, double(ours_triangles) / ours / 1e3, occt, occt_triangles, occt / ours);
    }
    // Cost against size: files of 1 to 256 tubes (written by the tests' STEP
    // writer), read and meshed at the default tolerance; linear cost keeps the
    // time per solid flat.
    std::printf("\n%-34s %9s %9s %10s %12s\n", "tubes in one file", "MB", "mbx ms", "triangles", "ms per tube");
    for (int tubes : {1, 4, 16, 64, 256}) {
        mbx_test::StepSolidWriter writer;
        for (int k = 0; k < tubes; ++k) writer.tube(0.02, 0.008, 0.05 * k, 0.05 * k + 0.035);
        const std::string text = writer.file();
        size_t triangles = 0;
        const double ms = best_ms(2, [&] {
            const mbx_step::File f = mbx_step::read_part21(text, "tubes.step");
            triangles = 0;
            for (const mbx_step::SolidMesh& m : mbx_step::tessellate(mbx_step::read_breps(f), mbx_step::Tolerance{}))
                triangles += m.mesh.triangles.size();
        });
        std::printf("%-34d %9.3f %9.1f %10zu %12.3f\n", tubes, double(text.size()) / 1e6, ms, triangles, ms / tubes);
    }
    return 0;
}
