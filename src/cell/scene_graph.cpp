#include "cell/scene_graph.hpp"

#include "cell/device_arguments.hpp"
#include "kb/rdf/turtle.hpp"

namespace skillcell::cell {

namespace {

namespace rdf = kb::rdf;

constexpr const char* kProc = "http://skillcell.dev/ontology/process#";

rdf::Term proc(const char* local) {
    return rdf::iri(std::string(kProc) + local);
}

class SceneWriter {
public:
    explicit SceneWriter(std::string ns) : ns_(std::move(ns)) {}

    rdf::Term resource(const std::string& name) const { return rdf::iri(ns_ + "#" + name); }
    void add(const rdf::Term& s, const rdf::Term& p, rdf::Term o) {
        triples_.push_back({s, p, std::move(o)});
    }
    void typed(const rdf::Term& s, const char* type) {
        add(s, rdf::iri(std::string(rdf::vocab::kRdf) + "type"), proc(type));
    }
    /// A proc:Pose node (a blank node: it belongs to its resource) with all six numbers.
    void pose(const rdf::Term& s, const char* property, const Pose& p) {
        const rdf::Term node = rdf::blank("pose" + std::to_string(++poses_));
        add(s, proc(property), node);
        typed(node, "Pose");
        const std::pair<const char*, double> parts[] = {
            {"x", p.x}, {"y", p.y}, {"z", p.z}, {"roll", p.a}, {"pitch", p.b}, {"yaw", p.c}};
        for (const auto& [local, value] : parts) add(node, proc(local), rdf::decimalLiteral(value));
    }
    std::vector<rdf::Triple> take() { return std::move(triples_); }

private:
    std::string ns_;
    std::vector<rdf::Triple> triples_;
    int poses_ = 0;
};

}  // namespace

std::string sceneGraphIri(const CellFile& cell) {
    return "http://skillcell.dev/cell/" + cell.name;
}

std::vector<kb::rdf::Triple> sceneTriples(const CellFile& cell) {
    SceneWriter w(sceneGraphIri(cell));
    for (const auto& d : cell.docks) {
        const auto dock = w.resource(d.name);
        w.typed(dock, "ToolDock");
        w.pose(dock, "pose", d.pose);
        for (const auto& t : cell.tools) {
            if (t.dock == d.name) w.add(dock, proc("holds"), w.resource(t.name));
        }
    }
    for (const auto& t : cell.tools) {
        const auto tool = w.resource(t.name);
        w.typed(tool, "Tool");
        if (const AdapterModel* m = findAdapterModel(t.adapter)) {
            w.add(tool, proc("gripType"), rdf::literal(std::string(m->gripType)));
        }
    }
    for (const auto& o : cell.objects) {
        const auto object = w.resource(o.name);
        w.typed(object, "PhysicalObject");
        w.add(object, proc("objectId"), rdf::literal(o.name));
        w.pose(object, "pose", o.pose);
        // What a gripper must be able to hold (the MES checks MaxPayload and MaxGripWidth).
        w.add(object, proc("sizeX"), rdf::decimalLiteral(o.size[0]));
        w.add(object, proc("sizeY"), rdf::decimalLiteral(o.size[1]));
        w.add(object, proc("sizeZ"), rdf::decimalLiteral(o.size[2]));
        if (o.mass) w.add(object, proc("mass"), rdf::decimalLiteral(*o.mass));
    }
    return w.take();
}

}  // namespace skillcell::cell
