// The tests' independent reading of a STEP file: OpenCASCADE 7.6 (test-only,
// docs/dependencies.md). For each solid of the transferred shape, one line:
//   solid <faces> <edges> <vertices> <volume m^3> <cx> <cy> <cz> <Ixx> <Iyy> <Izz> <Ixy> <Ixz> <Iyz>
// in metres (the inertia about the centroid, unit density, products as
// +integral xy dm), then "distinct <faces> <edges> <vertices>" over the solids'
// shared definitions (placed copies counted once).
#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <STEPControl_Reader.hxx>
#include <TopAbs_ShapeEnum.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Shape.hxx>

#include <cstdio>
#include <set>
#include <string>

int main(int argc, char** argv) {
    if (argc != 2 && !(argc == 3 && std::string(argv[2]) == "--faces")) {
        std::fprintf(stderr, "usage: %s file.step [--faces]\n", argv[0]);
        return 2;
    }
    const bool faces_too = argc == 3;
    Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_Printer));
    STEPControl_Reader reader;
    Interface_Static::SetCVal("xstep.cascade.unit", "M");
    if (reader.ReadFile(argv[1]) != IFSelect_RetDone) {
        std::fprintf(stderr, "OpenCASCADE cannot read %s\n", argv[1]);
        return 1;
    }
    reader.TransferRoots();
    const TopoDS_Shape shape = reader.OneShape();
    std::set<const void*> faces, edges, vertices;
    for (TopExp_Explorer solids(shape, TopAbs_SOLID); solids.More(); solids.Next()) {
        const TopoDS_Shape& solid = solids.Current();
        TopTools_IndexedMapOfShape f, e, v;
        TopExp::MapShapes(solid, TopAbs_FACE, f);
        TopExp::MapShapes(solid, TopAbs_EDGE, e);
        TopExp::MapShapes(solid, TopAbs_VERTEX, v);
        for (int k = 1; k <= f.Extent(); ++k) faces.insert(f(k).TShape().get());
        for (int k = 1; k <= e.Extent(); ++k) edges.insert(e(k).TShape().get());
        for (int k = 1; k <= v.Extent(); ++k) vertices.insert(v(k).TShape().get());
        GProp_GProps props;
        // The adaptive integration (to 1e-9): the default fixed Gauss order
        // misses some B-spline faces by 1e-3 (t20_data.step's, where
        // OpenCASCADE's own mesh agrees with mbx's and not with it).
        BRepGProp::VolumeProperties(solid, props, 1e-9, Standard_True);
        const gp_Pnt c = props.CentreOfMass();
        const gp_Mat I = props.MatrixOfInertia();
        // With --faces: "face <index> <surface type> <area m^2>" for each face, in the solid's order.
        for (int k = 1; faces_too && k <= f.Extent(); ++k) {
            GProp_GProps area;
            BRepGProp::SurfaceProperties(f(k), area, 1e-9);
            std::printf("face %d %d %.17g\n", k, int(BRepAdaptor_Surface(TopoDS::Face(f(k))).GetType()), area.Mass());
        }
        std::printf("solid %d %d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", f.Extent(), e.Extent(),
                    v.Extent(), props.Mass(), c.X(), c.Y(), c.Z(), I(1, 1), I(2, 2), I(3, 3), -I(1, 2), -I(1, 3), -I(2, 3));
    }
    std::printf("distinct %zu %zu %zu\n", faces.size(), edges.size(), vertices.size());
    return 0;
}
