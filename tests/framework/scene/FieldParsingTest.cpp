// Parsing and checking of field values, the same for attributes and --set.
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "framework/core/Component.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

// One field of every kind, with ranges, as a scene component would declare them.
class FieldZoo final : public Component {
 public:
  Field<bool> flag{this, "flag", false, {.help = "a bool"}};
  Field<int> count{this, "count", 1, {.help = "an int", .min = 1.0, .max = 10.0}};
  Field<double> gain{this, "gain", 1.0, {.help = "a double", .unit = "N/mm", .min = 0.0}};
  Field<double> radius{this, "radius", 1.0, {.help = "exclusive", .unit = "mm", .min = 0.0, .minExclusive = true}};
  Field<Vec3> offset{this, "offset", Vec3::Zero(), {.help = "a vec3", .min = -5.0, .max = 5.0}};
  Field<std::vector<double>> times{this, "times", {}, {.help = "a list", .min = 0.0}};
  Field<std::string> label{this, "label", "", {.help = "a string"}};
  EnumField shape{this, "shape", {"sphere", "cylinder", "cone"}, "sphere", {.help = "an enum"}};
  FilePathField input{this, "input", {.help = "an input file"}};
  FilePathField volume{this, "volume", {.help = "a file or a phantom"}, FilePathField::Role::Input, {"phantom"}};
  FilePathField output{this, "output", {.help = "an output file"}, FilePathField::Role::Output};
  FilePathField series{this, "series", {.help = "a file or a directory"}, FilePathField::Role::InputOrDirectory,
                       {"phantom"}};
  RateField rate{this, 100.0};
  Link<Component> other{this, "other", {.help = "a link"}};
};

const SourceLocation kWhere{"zoo.xml", 3, 7};

// The rejection message, or "" when the value was accepted.
std::string assign(BaseField& field, std::string_view text, const std::filesystem::path& base = {}) {
  const std::optional<std::string> error = field.assign(text, ParseContext{base}, kWhere);
  return error ? *error : "";
}

TEST(FieldParsingTest, BoolAcceptsTrueFalseOneAndZeroAroundBlanks) {
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.flag, "true"), "");
  EXPECT_TRUE(*zoo.flag);
  EXPECT_EQ(assign(zoo.flag, " 0 "), "");
  EXPECT_FALSE(*zoo.flag);
  EXPECT_EQ(assign(zoo.flag, "1"), "");
  EXPECT_TRUE(*zoo.flag);
  EXPECT_EQ(assign(zoo.flag, "yes"), "expected true or false, got 'yes'");
  EXPECT_EQ(assign(zoo.flag, "True"), "expected true or false, got 'True'");
  EXPECT_EQ(assign(zoo.flag, ""), "expected true or false, got ''");
}

TEST(FieldParsingTest, IntAcceptsSignedWholeNumbersInRange) {
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.count, "7"), "");
  EXPECT_EQ(*zoo.count, 7);
  EXPECT_EQ(assign(zoo.count, "+3"), "");
  EXPECT_EQ(*zoo.count, 3);
  EXPECT_EQ(assign(zoo.count, "2.5"), "expected an integer, got '2.5'");
  EXPECT_EQ(assign(zoo.count, "1e3"), "expected an integer, got '1e3'");
  EXPECT_EQ(assign(zoo.count, "+-3"), "expected an integer, got '+-3'");
  EXPECT_EQ(assign(zoo.count, "99999999999"), "integer '99999999999' is outside the range of an int");
  EXPECT_EQ(assign(zoo.count, ""), "expected an integer, got ''");
  EXPECT_EQ(assign(zoo.count, "0"), "value 0 is out of range [1, 10]");
  EXPECT_EQ(assign(zoo.count, "11"), "value 11 is out of range [1, 10]");
  EXPECT_EQ(*zoo.count, 3) << "a rejected value leaves the previous one";
}

TEST(FieldParsingTest, DoubleAcceptsDecimalAndExponentFormsOnly) {
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.gain, " 1.5 "), "");
  EXPECT_EQ(*zoo.gain, 1.5);
  EXPECT_EQ(assign(zoo.gain, "+2"), "");
  EXPECT_EQ(assign(zoo.gain, "1e-3"), "");
  EXPECT_EQ(*zoo.gain, 1e-3);
  EXPECT_EQ(assign(zoo.gain, "abc"), "expected a number, got 'abc'");
  EXPECT_EQ(assign(zoo.gain, "1.5mm"), "expected a number, got '1.5mm'");
  EXPECT_EQ(assign(zoo.gain, "nan"), "expected a finite number, got 'nan'");
  EXPECT_EQ(assign(zoo.gain, "inf"), "expected a finite number, got 'inf'");
  EXPECT_EQ(assign(zoo.gain, "++2"), "expected a number, got '++2'");
  EXPECT_EQ(assign(zoo.gain, "1e999"), "number '1e999' is outside the range of a double (about 1e-308 to 1e308)");
  EXPECT_EQ(assign(zoo.gain, ""), "expected a number, got an empty value");
  EXPECT_EQ(assign(zoo.gain, "-0.5"), "value -0.5 is out of range [0, inf) N/mm");
}

TEST(FieldParsingTest, ExclusiveMinimumRejectsTheLimitItself) {
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.radius, "0"), "value 0 is out of range (0, inf) mm");
  EXPECT_EQ(assign(zoo.radius, "1e-9"), "");
  EXPECT_EQ(zoo.radius.rangeText(), "(0, inf)");
}

TEST(FieldParsingTest, RateMustBePositiveAndAtMostAMegahertz) {
  FieldZoo zoo;
  EXPECT_EQ(zoo.rate.typeName(), "rate");
  EXPECT_EQ(assign(zoo.rate, "0"), "value 0 is out of range [0.001, 1e+06] Hz");
  EXPECT_EQ(assign(zoo.rate, "-60"), "value -60 is out of range [0.001, 1e+06] Hz");
  EXPECT_EQ(assign(zoo.rate, "1000001"), "value 1000001 is out of range [0.001, 1e+06] Hz");
  EXPECT_EQ(assign(zoo.rate, "1e6"), "");
  EXPECT_EQ(assign(zoo.rate, "0.5"), "");
  EXPECT_EQ(zoo.rateHz(), 0.5);
}

TEST(FieldParsingTest, Vec3TakesExactlyThreeNumbersSeparatedBySpacesOrCommas) {
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.offset, "1 2 3"), "");
  EXPECT_EQ(*zoo.offset, Vec3(1, 2, 3));
  EXPECT_EQ(assign(zoo.offset, "1,2,3"), "");
  EXPECT_EQ(assign(zoo.offset, " -1, 0.5 ,\t4 "), "");
  EXPECT_EQ(*zoo.offset, Vec3(-1, 0.5, 4));
  EXPECT_EQ(assign(zoo.offset, "1 2"), "expected three numbers 'x y z', got 2 value(s) in '1 2'");
  EXPECT_EQ(assign(zoo.offset, "1 2 3 4"), "expected three numbers 'x y z', got 4 value(s) in '1 2 3 4'");
  EXPECT_EQ(assign(zoo.offset, ""), "expected three numbers 'x y z', got 0 value(s) in ''");
  EXPECT_EQ(assign(zoo.offset, "1 a 3"), "expected a number, got 'a'");
  EXPECT_EQ(assign(zoo.offset, "0 0 6"), "value 6 is out of range [-5, 5]");
  EXPECT_EQ(zoo.offset.valueText(), "-1 0.5 4");
}

TEST(FieldParsingTest, ListTakesAnyCountIncludingNoneAndChecksEachElement) {
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.times, "0.5 1, 2"), "");
  EXPECT_EQ(*zoo.times, (std::vector<double>{0.5, 1, 2}));
  EXPECT_EQ(zoo.times.valueText(), "0.5 1 2");
  EXPECT_EQ(assign(zoo.times, ""), "");
  EXPECT_TRUE(zoo.times->empty());
  EXPECT_EQ(assign(zoo.times, "1 x"), "in list: expected a number, got 'x'");
  EXPECT_EQ(assign(zoo.times, "1 -2"), "value -2 is out of range [0, inf)");
}

TEST(FieldParsingTest, StringKeepsTheTextAsGiven) {
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.label, "  spaced  "), "");
  EXPECT_EQ(*zoo.label, "  spaced  ");
}

TEST(FieldParsingTest, EnumAcceptsExactlyOneOfItsOptionsAndSuggestsTheClosest) {
  FieldZoo zoo;
  EXPECT_EQ(zoo.shape.rangeText(), "one of: sphere, cylinder, cone");
  EXPECT_EQ(assign(zoo.shape, " cone "), "");
  EXPECT_TRUE(zoo.shape.is("cone"));
  EXPECT_EQ(zoo.shape.index(), 2u);
  EXPECT_EQ(assign(zoo.shape, "cylnder"),
            "expected one of: sphere, cylinder, cone, got 'cylnder', did you mean 'cylinder'?");
  EXPECT_EQ(assign(zoo.shape, "Sphere"),
            "expected one of: sphere, cylinder, cone, got 'Sphere', did you mean 'sphere'?");
  EXPECT_EQ(assign(zoo.shape, "pyramid"), "expected one of: sphere, cylinder, cone, got 'pyramid'");
  EXPECT_TRUE(zoo.shape.is("cone"));
}

TEST(FieldParsingTest, InputFileResolvesAgainstTheSettingFilesDirectoryAndMustExist) {
  test::TempDir dir;
  const auto data = dir.write("data/stream.csv", "t\n");
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.input, "data/stream.csv", dir.path()), "");
  EXPECT_EQ(zoo.input.path(), data);
  EXPECT_EQ(zoo.input.text(), "data/stream.csv");
  EXPECT_FALSE(zoo.input.isScheme());
  EXPECT_EQ(assign(zoo.input, data.string(), "/nowhere"), "") << "an absolute path ignores the directory";
  EXPECT_EQ(assign(zoo.input, "data/../data/missing.csv", dir.path()),
            "file not found: " + (dir.path() / "data/missing.csv").string());
  EXPECT_EQ(assign(zoo.input, "data", dir.path()), "not a regular file: " + (dir.path() / "data").string());
  EXPECT_EQ(assign(zoo.input, "  ", dir.path()), "expected a file path, got an empty value");
  EXPECT_EQ(zoo.input.path(), data) << "a rejected value leaves the previous one";
}

TEST(FieldParsingTest, OutputFileNeedNotExist) {
  test::TempDir dir;
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.output, "out/new.csv", dir.path()), "");
  EXPECT_EQ(zoo.output.path(), dir.path() / "out/new.csv");
}

TEST(FieldParsingTest, SchemeIsAcceptedOnlyByAFieldThatListsIt) {
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.volume, "phantom:skull?voxel=1"), "");
  EXPECT_TRUE(zoo.volume.isScheme());
  EXPECT_EQ(zoo.volume.scheme(), "phantom");
  EXPECT_EQ(zoo.volume.schemeBody(), "skull?voxel=1");
  EXPECT_TRUE(zoo.volume.path().empty());
  EXPECT_EQ(zoo.volume.rangeText(), "existing file or phantom:...");

  EXPECT_EQ(assign(zoo.volume, "mesh:skull"), "unknown source 'mesh:', expected a file path or phantom:...");
  EXPECT_EQ(assign(zoo.input, "phantom:skull?voxel=1"), "unknown source 'phantom:', expected a file path");
}

// A DICOM series is a directory, and one series among several is picked by a
// query after it, which the path keeps for the reader.
TEST(FieldParsingTest, AFieldForSeriesTakesADirectoryAndAQueryAfterIt) {
  FieldZoo zoo;
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "ct");
  dir.write("ct/a.dcm", "x");
  EXPECT_EQ(assign(zoo.series, "ct/", dir.path()), "");
  EXPECT_EQ(zoo.series.path(), (dir.path() / "ct/").lexically_normal());
  EXPECT_EQ(assign(zoo.series, "ct/?series=1.2.3", dir.path()), "");
  EXPECT_EQ(zoo.series.path().string(), (dir.path() / "ct").string() + "?series=1.2.3");
  EXPECT_EQ(assign(zoo.series, "ct/a.dcm", dir.path()), "");
  EXPECT_EQ(assign(zoo.series, "ct/a.dcm?series=1", dir.path()),
            "'?series=1' follows a file: a query picks within a directory (a DICOM series), e.g. DIR/?series=UID");
  EXPECT_EQ(assign(zoo.series, "none/", dir.path()), "file or directory not found: " + (dir.path() / "none/").string());
  EXPECT_EQ(zoo.series.rangeText(), "existing file or directory or phantom:...");
  // A plain input still wants a file.
  EXPECT_EQ(assign(zoo.input, "ct", dir.path()), "not a regular file: " + (dir.path() / "ct").string());
}

TEST(FieldParsingTest, OneLetterBeforeAColonIsAPathNotAScheme) {
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.input, "C:/scenes/x.csv", "/base"), "file not found: /base/C:/scenes/x.csv");
}

TEST(FieldParsingTest, LinkNeedsAnAtSignAndAPath) {
  FieldZoo zoo;
  EXPECT_EQ(assign(zoo.other, " @../tool/device "), "");
  EXPECT_EQ(zoo.other.path(), "../tool/device");
  EXPECT_EQ(zoo.other.valueText(), "@../tool/device");
  EXPECT_EQ(zoo.other.typeName(), "link<Component>");
  EXPECT_EQ(assign(zoo.other, "device"), "expected a link '@path' to a Component, got 'device'");
  EXPECT_EQ(assign(zoo.other, "@"), "expected a link '@path' to a Component, got '@'");
}

TEST(FieldParsingTest, AcceptedValueRemembersWhereItWasSet) {
  FieldZoo zoo;
  zoo.setLocation({"zoo.xml", 3, 1});
  EXPECT_FALSE(zoo.gain.isSet());
  EXPECT_EQ(zoo.gain.location().str(), "zoo.xml:3:1") << "unset: the owner's element";
  EXPECT_NE(assign(zoo.gain, "bad"), "");
  EXPECT_FALSE(zoo.gain.isSet());
  EXPECT_EQ(assign(zoo.gain, "2"), "");
  EXPECT_TRUE(zoo.gain.isSet());
  EXPECT_EQ(zoo.gain.location().str(), "zoo.xml:3:7");
}

TEST(FieldParsingTest, ValidatorAddsARuleAfterParsingAndRange) {
  FieldZoo zoo;
  zoo.offset.setValidator([](const Vec3& v) -> std::optional<std::string> {
    if (v.norm() == 0) return "must not be zero";
    return std::nullopt;
  });
  EXPECT_EQ(assign(zoo.offset, "0 0 0"), "must not be zero");
  EXPECT_EQ(assign(zoo.offset, "0 0 9"), "value 9 is out of range [-5, 5]");
  EXPECT_EQ(assign(zoo.offset, "0 0 1"), "");
}

TEST(FieldParsingTest, TypeNamesDefaultsAndRangesAsShownInTheReference) {
  FieldZoo zoo;
  EXPECT_EQ(zoo.flag.typeName(), "bool");
  EXPECT_EQ(zoo.count.typeName(), "int");
  EXPECT_EQ(zoo.gain.typeName(), "double");
  EXPECT_EQ(zoo.offset.typeName(), "vec3");
  EXPECT_EQ(zoo.times.typeName(), "list<double>");
  EXPECT_EQ(zoo.shape.typeName(), "enum");
  EXPECT_EQ(zoo.input.typeName(), "file");
  EXPECT_EQ(zoo.count.rangeText(), "[1, 10]");
  EXPECT_EQ(zoo.gain.rangeText(), "[0, inf)");
  EXPECT_EQ(zoo.label.rangeText(), "");
  EXPECT_EQ(zoo.offset.defaultText(), "0 0 0");
  EXPECT_EQ(zoo.shape.defaultText(), "sphere");
  EXPECT_EQ(zoo.rate.defaultText(), "100");
}

}  // namespace
}  // namespace trephine
