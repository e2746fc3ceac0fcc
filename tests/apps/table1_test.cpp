// The paper's Table 1 (bench/table1/table1.h) for the unit cube, and the mesh listing.
#include "bench/table1/table1.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "tests/paths.h"

namespace oct {
namespace {

TEST(Table1, CountsOfTheUnitCube) {
    Table1Row r = table1Row(octtest::meshPath("cube_binary.ply"), BuildParams{});
    EXPECT_EQ(r.name, "cube_binary.ply");
    EXPECT_EQ(r.vertices, 8u);
    EXPECT_EQ(r.faces, 12u);
    EXPECT_EQ(r.octreeFaces, 48u);  // each face triangle in the 4 leaves of its side
    std::vector<std::string> meshes = table1Meshes(std::string(OCT_SOURCE_DIR) + "/meshes");
    EXPECT_GE(meshes.size(), octtest::committedMeshes().size());
    EXPECT_NE(humanTable1({r}).find("cube_binary.ply"), std::string::npos);
    EXPECT_THROW(table1Meshes(std::string(OCT_SOURCE_DIR) + "/no-such-dir"), std::runtime_error);
}

}  // namespace
}  // namespace oct
