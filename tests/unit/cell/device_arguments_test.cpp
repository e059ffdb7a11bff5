// From a cell file to device command lines (src/cell/device_arguments): the paper's cell
// gives the world scene and the tool table that the demo wrote by hand before it read the
// file, option for option.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cell/cell_file.hpp"
#include "cell/device_arguments.hpp"

namespace skillcell::cell::device_arguments_test {
namespace {

namespace fs = std::filesystem;
using Args = std::vector<std::string>;

CellFile paperCell() {
    auto read = readCellFile(fs::path(SKILLCELL_SOURCE_DIR) / "examples/cells/paper.toml");
    EXPECT_TRUE(read.cell);
    return read.cell ? *read.cell : CellFile{};
}

TEST(DeviceArguments, TheWorldGetsThePapersDocksToolsAndBoxes) {
    EXPECT_EQ(worldArguments(paperCell()),
              (Args{"--robot", "ur5@0,0,0", "--dock", "dockP@0.3,-0.45,0.35,3.141592653589793,0,0",
                    "--dock", "dockV@0.45,-0.3,0.35,3.141592653589793,0,0", "--tool",
                    "parallel:dockP@0,0,0.15", "--tool", "vacuum:dockV@0,0,0.12", "--object",
                    "boxA:0.04,0.1,0.05@0.45,0.15,0.025", "--object",
                    "boxB:0.04,0.04,0.04@0.45,-0.05,0.02"}));
}

TEST(DeviceArguments, TheFuseBoxCellGivesItsSlotsAndFusesAndAMisalignmentOnlyWhereSaid) {
    auto read = readCellFile(fs::path(SKILLCELL_SOURCE_DIR) / "examples/cells/fuse-box.toml");
    ASSERT_TRUE(read.cell);
    CellFile cell = *read.cell;
    ASSERT_EQ(cell.fuseSlots.size(), 3U);
    cell.fuseSlots[1].misalignment = {0.0015, 0, 0};
    const Args args = worldArguments(cell);
    const Args expected = {"--robot",
                           "iiwa@0,0,0",
                           "--dock",
                           "dockP@0.35,-0.4,0.35,3.141592653589793,0,0",
                           "--tool",
                           "parallel:dockP@0,0,0.15",
                           "--fuse-slot",
                           "F1@0.45,0.25,0.06",
                           "--fuse-slot",
                           "F2@0.45,0.262,0.06",
                           "--misaligned-slot",
                           "F2:0.0015,0,0",
                           "--fuse-slot",
                           "F3@0.45,0.274,0.06",
                           "--fuse",
                           "fuse10A:0.0191,0.0051,0.0185@0.45,-0.05,0.00925,0,0,3.141592653589793",
                           "--fuse",
                           "fuse15A:0.0191,0.0051,0.0185@0.45,-0.03,0.00925,0,0,3.141592653589793",
                           "--fuse",
                           "fuse20A:0.0191,0.0051,0.0185@0.45,-0.01,0.00925,0,0,3.141592653589793"};
    EXPECT_EQ(args, expected);
}

TEST(DeviceArguments, TheToolChangerGetsEachToolsBandAdapterAndPowerCommand) {
    const auto power = [](const Tool& tool, const AdapterModel& model) {
        return "skillcell device " + std::string(model.command) + " --grip-offset " +
               vectorArgument(tool.gripOffset);
    };
    EXPECT_EQ(toolTableArguments(paperCell(), power),
              (Args{"--tool", "parallel:1-1.5:urn:skillcell:device:robotiq-2f85", "--power",
                    "parallel=skillcell device robotiq --grip-offset 0,0,0.15", "--tool",
                    "vacuum:2-2.5:urn:skillcell:device:schmalz-ecbpi", "--power",
                    "vacuum=skillcell device schmalz --grip-offset 0,0,0.12"}));
}

TEST(DeviceArguments, PosesReadBackAsTheSameNumbers) {
    EXPECT_EQ(poseArgument({0.1, -0.2, 0.3, 0, 0, 0}), "0.1,-0.2,0.3");
    EXPECT_EQ(poseArgument({1, 2, 3, 0, 0.5, 0}), "1,2,3,0,0.5,0");
    EXPECT_EQ(poseArgument({0.1 + 0.2, 0, 0, 0, 0, 0}), "0.30000000000000004,0,0");
}

TEST(DeviceArguments, EveryAdapterModelHasACommandAndAUri) {
    ASSERT_FALSE(adapterModelTable().empty());
    for (const auto& m : adapterModelTable()) {
        EXPECT_EQ(findAdapterModel(m.name), &m);
        EXPECT_FALSE(m.command.empty());
        EXPECT_EQ(m.applicationUri.rfind("urn:skillcell:device:", 0), 0U) << m.applicationUri;
    }
    EXPECT_EQ(findAdapterModel("robotiq-3f"), nullptr);
}

}  // namespace
}  // namespace skillcell::cell::device_arguments_test
