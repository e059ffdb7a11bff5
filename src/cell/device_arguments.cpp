#include "cell/device_arguments.hpp"

#include <array>
#include <charconv>

namespace skillcell::cell {
namespace {

/// The shortest text that reads back as the same double (std::to_chars' guarantee).
std::string number(double v) {
    std::array<char, 32> text{};
    const auto [end, ec] = std::to_chars(text.data(), text.data() + text.size(), v);
    return ec == std::errc() ? std::string(text.data(), end) : std::string("nan");
}

}  // namespace

const std::vector<AdapterModel>& adapterModelTable() {
    static const std::vector<AdapterModel> table = {
        {"robotiq-2f85", "robotiq", "urn:skillcell:device:robotiq-2f85", "parallel"},
        {"dh-ag95", "ag95", "urn:skillcell:device:dh-ag95", "parallel"},
        {"schmalz-ecbpi", "schmalz", "urn:skillcell:device:schmalz-ecbpi", "vacuum"},
    };
    return table;
}

const AdapterModel* findAdapterModel(std::string_view name) {
    for (const auto& m : adapterModelTable()) {
        if (m.name == name) return &m;
    }
    return nullptr;
}

AdapterComponent adapterComponent(const AdapterModel& model, std::string_view changer) {
    AdapterComponent c{std::string(model.command), std::string(model.applicationUri)};
    if (!changer.empty() && changer != ToolChanger{}.name) {
        c.name += "-" + std::string(changer);
        c.applicationUri += ":" + std::string(changer);
    }
    return c;
}

std::string vectorArgument(const std::array<double, 3>& v) {
    return number(v[0]) + "," + number(v[1]) + "," + number(v[2]);
}

std::string poseArgument(const Pose& pose) {
    std::string out = vectorArgument({pose.x, pose.y, pose.z});
    if (pose.a != 0 || pose.b != 0 || pose.c != 0) {
        out += "," + vectorArgument({pose.a, pose.b, pose.c});
    }
    return out;
}

std::string objectArgument(const WorldObject& object) {
    return object.name + ":" + vectorArgument(object.size) + "@" + poseArgument(object.pose);
}

std::vector<std::string> worldArguments(const CellFile& cell) {
    std::vector<std::string> args;
    for (const auto& r : cell.robots) {
        args.insert(args.end(), {"--robot", r.name + "@" + poseArgument(r.base)});
    }
    for (const auto& d : cell.docks) {
        args.insert(args.end(), {"--dock", d.name + "@" + poseArgument(d.pose)});
    }
    for (const auto& t : cell.tools) {
        args.insert(args.end(),
                    {"--tool", t.name + ":" + t.dock + "@" + vectorArgument(t.gripOffset)});
    }
    for (const auto& r : cell.rails) {
        args.insert(args.end(),
                    {"--rail", r.name + ":" + number(r.length) + "@" + poseArgument(r.pose)});
    }
    for (const auto& s : cell.fuseSlots) {
        args.insert(args.end(), {"--fuse-slot", s.name + "@" + poseArgument(s.pose)});
        if (s.misalignment != std::array<double, 3>{}) {
            args.insert(args.end(),
                        {"--misaligned-slot", s.name + ":" + vectorArgument(s.misalignment)});
        }
    }
    for (const auto& o : cell.objects) {
        const char* option = o.kind == WorldObject::Kind::TerminalBlock ? "--terminal-block"
                             : o.kind == WorldObject::Kind::Fuse        ? "--fuse"
                                                                        : "--object";
        args.insert(args.end(), {option, objectArgument(o)});
    }
    return args;
}

std::vector<std::string> toolTableArguments(const CellFile& cell, const PowerCommand& power,
                                            const std::string& changer) {
    std::vector<std::string> args;
    for (const auto& t : cell.tools) {
        if (!changer.empty() && t.changer != changer) continue;
        const AdapterModel* model = findAdapterModel(t.adapter);
        if (model == nullptr) continue;  // readCellFile refuses such a file
        args.insert(args.end(), {"--tool", t.name + ":" + number(t.pinVoltage[0]) + "-" +
                                               number(t.pinVoltage[1]) + ":" +
                                               adapterComponent(*model, t.changer).applicationUri});
        args.insert(args.end(), {"--power", t.name + "=" + power(t, *model)});
    }
    return args;
}

}  // namespace skillcell::cell
