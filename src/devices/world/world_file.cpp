#include "devices/world/world_file.hpp"

#include <fstream>
#include <nlohmann/json.hpp>

#include "common/atomic_file.hpp"

namespace skillcell::devices {

namespace {

using nlohmann::json;

constexpr const char* kFormat = "skillcell world 1";

json frameJson(const KDL::Frame& f) {
    json a = json::array({f.p.x(), f.p.y(), f.p.z()});
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) a.push_back(f.M(r, c));
    }
    return a;
}

json vectorJson(const KDL::Vector& v) {
    return json::array({v.x(), v.y(), v.z()});
}

const char* kindName(ObjectKind k) {
    switch (k) {
        case ObjectKind::TerminalBlock:
            return "terminal-block";
        case ObjectKind::Fuse:
            return "fuse";
        case ObjectKind::Box:
            break;
    }
    return "box";
}

json contentsJson(const WorldContents& w) {
    json j;
    j["format"] = kFormat;
    j["revision"] = w.revision;
    json& objects = j["objects"] = json::object();
    for (const auto& [id, o] : w.objects) {
        objects[id] = {{"size", {o.size.x, o.size.y, o.size.z}},
                       {"pose", frameJson(o.pose)},
                       {"kind", kindName(o.kind)},
                       {"grasps", o.grasps}};
    }
    json& tools = j["tools"] = json::object();
    for (const auto& [id, t] : w.tools) tools[id] = {{"gripPoint", frameJson(t.gripPoint)}};
    json& docks = j["docks"] = json::object();
    for (const auto& [id, d] : w.docks) docks[id] = {{"pose", frameJson(d.pose)}, {"tool", d.tool}};
    json& rails = j["rails"] = json::object();
    for (const auto& [id, r] : w.rails) {
        rails[id] = {{"pose", frameJson(r.pose)}, {"length", r.length}, {"width", r.width}};
    }
    json& mounts = j["railMounts"] = json::object();
    for (const auto& [id, m] : w.railMounts) {
        mounts[id] = {{"rail", m.rail}, {"position", m.position}};
    }
    json& robots = j["robots"] = json::object();
    for (const auto& [id, f] : w.robots) {
        json r = {{"base", frameJson(f.base)},
                  {"pose", frameJson(f.pose)},
                  {"tool", f.tool},
                  {"held", f.held},
                  {"toHeld", frameJson(f.toHeld)},
                  {"tilted", f.tilted},
                  {"snapped", f.snapped},
                  {"railRefusal", f.railRefusal}};
        if (f.hooked) r["hooked"] = {{"rail", f.hooked->rail}, {"position", f.hooked->position}};
        if (f.fuseContact) {
            const SlotContact& c = f.fuseContact->second;
            r["fuseContact"] = {{"slot", f.fuseContact->first},
                                {"depth", c.depth},
                                {"misalignment", c.misalignment},
                                {"aligned", c.aligned},
                                {"force", c.force}};
        }
        robots[id] = std::move(r);
    }
    json& slots = j["fuseSlots"] = json::object();
    for (const auto& [id, s] : w.fuseSlots) {
        slots[id] = {{"pose", frameJson(s.pose)},
                     {"depth", s.depth},
                     {"clearance", s.clearance},
                     {"misalignment", vectorJson(s.misalignment)}};
    }
    j["seatedFuses"] = w.seatedFuses;
    return j;
}

// Readers: each throws nlohmann's type_error or out_of_range for what is missing or of the
// wrong type; loadWorldFile turns that into an Error naming the file.
double number(const json& j) {
    if (!j.is_number()) throw std::invalid_argument("expected a number, found " + j.dump());
    return j.get<double>();
}

KDL::Frame frameOf(const json& j) {
    if (!j.is_array() || j.size() != 12) {
        throw std::invalid_argument("expected a frame [x, y, z, r00 .. r22], found " + j.dump());
    }
    KDL::Frame f;
    f.p = KDL::Vector(number(j[0]), number(j[1]), number(j[2]));
    f.M = KDL::Rotation(number(j[3]), number(j[4]), number(j[5]), number(j[6]), number(j[7]),
                        number(j[8]), number(j[9]), number(j[10]), number(j[11]));
    return f;
}

KDL::Vector vectorOf(const json& j) {
    if (!j.is_array() || j.size() != 3) {
        throw std::invalid_argument("expected [x, y, z], found " + j.dump());
    }
    return {number(j[0]), number(j[1]), number(j[2])};
}

ObjectKind kindOf(const std::string& name) {
    if (name == "box") return ObjectKind::Box;
    if (name == "terminal-block") return ObjectKind::TerminalBlock;
    if (name == "fuse") return ObjectKind::Fuse;
    throw std::invalid_argument("unknown object kind '" + name + "'");
}

WorldContents contentsOf(const json& j) {
    if (!j.is_object() || j.value("format", "") != kFormat) {
        throw std::invalid_argument(std::string("not a world file (\"format\": \"") + kFormat +
                                    "\")");
    }
    WorldContents w;
    w.revision = j.at("revision").get<std::uint64_t>();
    for (const auto& [id, o] : j.at("objects").items()) {
        const KDL::Vector size = vectorOf(o.at("size"));
        w.objects[id] = {id,
                         {size.x(), size.y(), size.z()},
                         frameOf(o.at("pose")),
                         kindOf(o.at("kind").get<std::string>()),
                         o.at("grasps").get<std::uint32_t>()};
    }
    for (const auto& [id, t] : j.at("tools").items()) {
        w.tools[id] = {id, frameOf(t.at("gripPoint"))};
    }
    for (const auto& [id, d] : j.at("docks").items()) {
        w.docks[id] = {id, frameOf(d.at("pose")), d.at("tool").get<std::string>()};
    }
    for (const auto& [id, r] : j.at("rails").items()) {
        w.rails[id] = {id, frameOf(r.at("pose")), number(r.at("length")), number(r.at("width"))};
    }
    for (const auto& [id, m] : j.at("railMounts").items()) {
        w.railMounts[id] = {m.at("rail").get<std::string>(), number(m.at("position"))};
    }
    for (const auto& [id, r] : j.at("robots").items()) {
        Flange f;
        f.base = frameOf(r.at("base"));
        f.pose = frameOf(r.at("pose"));
        f.tool = r.at("tool").get<std::string>();
        f.held = r.at("held").get<std::string>();
        f.toHeld = frameOf(r.at("toHeld"));
        f.tilted = r.at("tilted").get<bool>();
        f.snapped = r.at("snapped").get<bool>();
        f.railRefusal = r.at("railRefusal").get<std::string>();
        if (r.contains("hooked")) {
            const json& h = r["hooked"];
            f.hooked = RailMount{h.at("rail").get<std::string>(), number(h.at("position"))};
        }
        if (r.contains("fuseContact")) {
            const json& c = r["fuseContact"];
            SlotContact contact;
            contact.depth = number(c.at("depth"));
            contact.misalignment = number(c.at("misalignment"));
            contact.aligned = c.at("aligned").get<bool>();
            contact.force = number(c.at("force"));
            f.fuseContact = std::make_pair(c.at("slot").get<std::string>(), contact);
        }
        w.robots[id] = std::move(f);
    }
    for (const auto& [id, s] : j.at("fuseSlots").items()) {
        FuseSlot slot;
        slot.id = id;
        slot.pose = frameOf(s.at("pose"));
        slot.depth = number(s.at("depth"));
        slot.clearance = number(s.at("clearance"));
        slot.misalignment = vectorOf(s.at("misalignment"));
        w.fuseSlots[id] = slot;
    }
    w.seatedFuses = j.at("seatedFuses").get<std::map<std::string, std::string>>();
    return w;
}

}  // namespace

Expected<WorldContents> loadWorldFile(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) return Error{"cannot read " + file.string()};
    const json j = json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) return Error{file.string() + ": not JSON"};
    // The readers report what is wrong by exception; none leaves this function.
    try {
        return contentsOf(j);
    } catch (const std::exception& e) {
        return Error{file.string() + ": " + e.what()};
    }
}

Status saveWorldFile(const std::filesystem::path& file, const World& world) {
    // Not flushed to disk on every change (the flange moves 100 times a second): what this
    // guards against is the world process dying, after which the kernel still writes the file.
    if (!writeFileAtomically(file, contentsJson(world.contents()).dump() + "\n", 0644,
                             Flush::ToKernel)) {
        return Error{"cannot replace " + file.string()};
    }
    return Done{};
}

}  // namespace skillcell::devices
