// docs/scene-reference.md is generated from the scene reader's key tables (io/scene/): it must be what the
// tables generate now, so that a key added, removed or changed in a table is documented in the same commit.
#include <string>

#include <gtest/gtest.h>

#include "io/scene_reader.hpp"
#include "support/test_support.hpp"

namespace vitrum {
namespace {

TEST(SceneReference, CommittedDocumentIsWhatTheKeyTablesGenerate) {
    const std::string path = std::string(VITRUM_SOURCE_DIR) + "/docs/scene-reference.md";
    const std::string generated = sceneReferenceMarkdown();
    EXPECT_TRUE(testing::readText(path) == generated)
        << path << " differs from what the key tables generate; regenerate it with\n"
        << "    build/vitrum scene-reference > docs/scene-reference.md";
}

TEST(SceneReference, ListsEveryKeyWithItsUnitAndDefault) {
    const std::string doc = sceneReferenceMarkdown();
    for (const char* line : {"## [sample]", "| `radius` | length | number > 0 | 5.0 um |", "## [[stage]]",
                             "| `duration` | time | number > 0 | required |",
                             "| `lattice` | - | \"sc\", \"fcc\", \"random\" | \"fcc\" |"}) {
        EXPECT_NE(doc.find(line), std::string::npos) << "'" << line << "' missing from:\n" << doc;
    }
}

} // namespace
} // namespace vitrum
