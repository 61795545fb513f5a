// The tests' independent reading of a STEP file: OpenCASCADE 7.6 (test-only,
// docs/dependencies.md). For each solid of the transferred shape, one line:
//   solid <faces> <edges> <vertices> <volume m^3> <cx> <cy> <cz> <Ixx> <Iyy> <Izz> <Ixy> <Ixz> <Iyz>
// in metres (the inertia about the centroid, unit density, products as
// +integral xy dm), then "distinct <faces> <edges> <vertices>" over the solids'
// shared definitions (placed copies counted once). With --distance <file>
// (a point per line, "x y z [reach]" in metres), instead one line per point:
//   distance <metres from the point to the nearest face of the shape> gap <metres>
// where gap is the largest tolerance OpenCASCADE gives an edge within reach.
#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <BRepBndLib.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <Bnd_Box.hxx>
#include <ShapeAnalysis_Curve.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Geom_Surface.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Compound.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
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

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <vector>
#include <set>
#include <string>

int main(int argc, char** argv) {
    const bool distances = argc == 4 && std::string(argv[2]) == "--distance";
    if (argc != 2 && !(argc == 3 && std::string(argv[2]) == "--faces") && !distances) {
        std::fprintf(stderr, "usage: %s file.step [--faces | --distance points.txt]\n", argv[0]);
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
    if (distances) {
        // Per face: the point projected onto the face's surface, where the
        // projection lies inside the face (BRepExtrema alone misses B-spline
        // faces: 7.5 mm off on t20_data.step where a projection finds 1e-7 m);
        // per edge, the point projected onto the edge's curve, for points
        // just beyond a face's rim (BRepExtrema put the middle of a 5 µm
        // chord between two points on linkrods.step's edges 0.15 mm away).
        std::vector<TopoDS_Face> all;
        std::vector<Bnd_Box> boxes;
        TopoDS_Compound faces;
        BRep_Builder builder;
        builder.MakeCompound(faces);
        for (TopExp_Explorer f(shape, TopAbs_FACE); f.More(); f.Next()) {
            all.push_back(TopoDS::Face(f.Current()));
            boxes.emplace_back();
            BRepBndLib::Add(f.Current(), boxes.back());
            builder.Add(faces, f.Current());
        }
        std::vector<TopoDS_Edge> edges;
        std::vector<Bnd_Box> edge_boxes;
        TopTools_IndexedMapOfShape edge_map;
        TopExp::MapShapes(shape, TopAbs_EDGE, edge_map);
        for (int k = 1; k <= edge_map.Extent(); ++k) {
            edges.push_back(TopoDS::Edge(edge_map(k)));
            edge_boxes.emplace_back();
            BRepBndLib::Add(edge_map(k), edge_boxes.back());
        }
        std::ifstream points(argv[3]);
        std::string line;
        while (std::getline(points, line)) {
            double x = 0, y = 0, z = 0, reach = 0;
            const int read = std::sscanf(line.c_str(), "%lf %lf %lf %lf", &x, &y, &z, &reach);
            if (read < 3) continue;
            const gp_Pnt p(x, y, z);
            BRepExtrema_DistShapeShape nearest(BRepBuilderAPI_MakeVertex(p).Vertex(), faces, Extrema_ExtFlag_MIN);
            if (!nearest.IsDone()) return 1;
            double best = nearest.Value();
            for (size_t k = 0; k < all.size(); ++k) {
                if (boxes[k].Distance(Bnd_Box(p, p)) >= best) continue;
                // (ShapeAnalysis_Surface: GeomAPI_ProjectPointOnSurf finds no
                // foot point on linkrods.step's degree-6 rational fillets)
                ShapeAnalysis_Surface surface(BRep_Tool::Surface(all[k]));
                const gp_Pnt2d uv = surface.ValueOfUV(p, 1e-12);
                if (surface.Gap() >= best) continue;
                const BRepClass_FaceClassifier inside(all[k], uv, 1e-9);
                if (inside.State() == TopAbs_IN || inside.State() == TopAbs_ON) best = surface.Gap();
            }
            // The file's own gap near the point: the largest tolerance
            // OpenCASCADE gave an edge within `reach` of it (an exporter's
            // edge curve lying off one of its faces' surfaces by that much;
            // a mesh sharing the edge's points cannot be closer to both).
            double gap = 0;
            for (size_t k = 0; k < edges.size(); ++k) {
                const double box = edge_boxes[k].Distance(Bnd_Box(p, p));
                if (box >= best && box > reach) continue;
                const BRepAdaptor_Curve curve(edges[k]);
                gp_Pnt foot;
                double parameter = 0;
                const double d = ShapeAnalysis_Curve().Project(curve, p, 1e-12, foot, parameter);
                best = std::min(best, d);
                if (d <= reach) gap = std::max(gap, BRep_Tool::Tolerance(edges[k]));
            }
            std::printf("distance %.17g gap %.17g\n", best, gap);
        }
        return 0;
    }
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
