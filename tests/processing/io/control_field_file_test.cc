// The control field and hand-mark files: what is written reads back to the digit, and a mark
// belongs to the image whose path it ends at a separator.
#include "processing/io/control_field_file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/common/temp_dir.h"

namespace ts {
namespace {

TEST(ControlFieldFile, RoundTripsEveryTarget) {
  testing::TempDir dir;
  ControlField field;
  for (int i = 0; i < 8; ++i)
    field.targets.push_back({100 + i,
                             {512345.6789 + i, 4212345.1234 - i, 31.0041 * i},
                             i == 3 ? 0.0 : 0.0012,
                             0.06 + 0.01 * i});
  ASSERT_TRUE(SaveControlField(field, dir / "field.yaml").ok());
  const Result<ControlField> read = LoadControlField(dir / "field.yaml");
  ASSERT_TRUE(read.ok()) << read.error();
  ASSERT_EQ(read->targets.size(), field.targets.size());
  for (size_t i = 0; i < field.targets.size(); ++i) {
    EXPECT_EQ(read->targets[i].id, field.targets[i].id);
    EXPECT_LT((read->targets[i].position_m - field.targets[i].position_m).norm(), 1e-6);
    EXPECT_DOUBLE_EQ(read->targets[i].sigma_m, field.targets[i].sigma_m);
    EXPECT_DOUBLE_EQ(read->targets[i].diameter_m, field.targets[i].diameter_m);
  }
  EXPECT_EQ(read->IndexOf(104), 4);
  EXPECT_EQ(read->IndexOf(99), -1);
}

TEST(ControlFieldFile, TooFewTargetsOrAMissingDiameterIsAnError) {
  testing::TempDir dir;
  std::ofstream(dir / "few.yaml") << "control_field: {version: 1, targets: "
                                     "[{id: 1, x: 0, y: 0, z: 0, sigma_m: 0, diameter_m: 1}]}\n";
  std::ofstream(dir / "diameter.yaml") << "control_field: {version: 1, targets: "
                                          "[{id: 1, x: 0, y: 0, z: 0, sigma_m: 0}]}\n";
  const Result<ControlField> few = LoadControlField(dir / "few.yaml");
  ASSERT_FALSE(few.ok());
  EXPECT_NE(few.error().find("few.yaml: control_field.targets: a control field needs at least 6"),
            std::string::npos)
      << few.error();
  const Result<ControlField> diameter = LoadControlField(dir / "diameter.yaml");
  ASSERT_FALSE(diameter.ok());
  EXPECT_NE(diameter.error().find("control_field.targets[0].diameter_m: missing"),
            std::string::npos)
      << diameter.error();
}

TEST(TargetMarksFile, RoundTripsAndMatchesImagesByTheEndOfTheirPath) {
  testing::TempDir dir;
  const std::vector<ImageMarks> marks = {{"left/01.png", {{101, {12.25, 30.5}}, {102, {800, 9}}}},
                                         {"02.png", {{103, {1, 2}}}}};
  ASSERT_TRUE(SaveTargetMarks(marks, dir / "marks.yaml").ok());
  const Result<std::vector<ImageMarks>> read = LoadTargetMarks(dir / "marks.yaml");
  ASSERT_TRUE(read.ok()) << read.error();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ((*read)[0].marks[1].id, 102);
  EXPECT_EQ((*read)[0].marks[0].pixel, Eigen::Vector2d(12.25, 30.5));
  EXPECT_EQ(MarksOfImage(*read, "/data/session/left/01.png"), &(*read)[0]);
  EXPECT_EQ(MarksOfImage(*read, "left/01.png"), &(*read)[0]);
  EXPECT_EQ(MarksOfImage(*read, "/data/xleft/01.png"), nullptr);
  EXPECT_EQ(MarksOfImage(*read, "/data/right/02.png"), &(*read)[1]);
  EXPECT_EQ(MarksOfImage(*read, "/data/right/102.png"), nullptr);
}

// A request's JSON reads as the files do (YAML reads JSON), errors naming the field alone.
TEST(ControlFieldText, JsonReadsAsTheFileDoesAndErrorsNameTheField) {
  std::string targets;
  for (int i = 0; i < 6; ++i)
    targets += std::string(i ? "," : "") + R"({"id": )" + std::to_string(101 + i) +
               R"(, "x": 5.5, "y": 1, "z": 2, "sigma_m": 0.001, "diameter_m": 0.06})";
  const Result<ControlField> field =
      ParseControlField(R"({"control_field": {"version": 1, "targets": [)" + targets + "]}}");
  ASSERT_TRUE(field.ok()) << field.error();
  ASSERT_EQ(field->targets.size(), 6u);
  EXPECT_EQ(field->targets[5].id, 106);
  EXPECT_EQ(field->targets[0].position_m.x(), 5.5);

  const Result<ControlField> twice =
      ParseControlField(R"({"control_field": {"version": 1, "targets": [)" + targets + "," +
                        R"({"id": 103, "x": 0, "y": 0, "z": 0, "sigma_m": 0, "diameter_m": 1}]}})");
  ASSERT_FALSE(twice.ok());
  EXPECT_EQ(twice.error().rfind("control_field.targets[6].id: 103 twice", 0), 0u) << twice.error();

  const Result<std::vector<ImageMarks>> marks =
      ParseTargetMarks(R"({"marks": [{"image": "left/01.png", "targets": [{"id": 1, "x": 3}]}]})");
  ASSERT_FALSE(marks.ok());
  EXPECT_EQ(marks.error().rfind("marks[0].targets[0].y: missing", 0), 0u) << marks.error();
  EXPECT_FALSE(ParseTargetMarks("{\"marks\": [").ok());  // cut short: a syntax error, no throw
  EXPECT_FALSE(ParseTargetMarks("[1, 2]").ok());
}

}  // namespace
}  // namespace ts
