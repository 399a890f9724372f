// Malformed XML: one error at the first problem (the tree is not built from a
// broken file, so nothing else is reported), with the position of the mistake.
#include <gtest/gtest.h>

#include <string>

#include "tests/framework/scene/LoaderAssertions.h"

namespace trephine::test {
namespace {

const LocatedErrorCase kCases[] = {
    {"MismatchedEndTagPointsAtTheEndTagAndNamesTheOpenElement", R"(<Node name="root">
  <Recorder name="r"></Recordr>
</Node>)",
     "inline.xml:2:22", "malformed XML: end tag </Recordr> does not match <Recorder> opened at line 2, column 3"},
    {"UnclosedAttributeValueIsReportedAtTheValueWithWhereItRanInto", R"(<Node name="root">
  <Recorder name="r/>
</Node>)",
     "inline.xml:2:19", "malformed XML: value of attribute 'name' is not closed before the '<' at line 3, column 1"},
    {"AttributeValueUnclosedAtEndOfFile", R"(<Node name="root)", "inline.xml:1:13",
     "malformed XML: value of attribute 'name' is not closed"},
    {"MissingEqualsSignIsReportedWhereItWasExpected", R"(<Node name="root">
  <Recorder name "r"/>
</Node>)",
     "inline.xml:2:18", "malformed XML: expected '=' after attribute 'name'"},
    {"UnquotedValueIsReported", R"(<Node name="root">
  <Recorder name=r/>
</Node>)",
     "inline.xml:2:18", "malformed XML: expected a quoted value for attribute 'name'"},
    {"ElementUnclosedAtEndOfFileIsReportedAtItsStart", R"(<Node name="root">
  <Node name="a"/>
)",
     "inline.xml:1:1", "malformed XML: element <Node> is never closed"},
    {"StartTagUnclosedAtEndOfFile", R"(<Node name="root")", "inline.xml:1:1",
     "malformed XML: start tag <Node> is not closed with '>'"},
    {"SecondRootElementIsReportedAtItsStart", R"(<Node name="root"/>
<Node name="two"/>)",
     "inline.xml:2:1", "a scene file has one root element; found a second one <Node>"},
    {"TextInsideAnElementIsReportedAtItsFirstCharacter", R"(<Node name="root">
  <Node name="a">hello</Node>
</Node>)",
     "inline.xml:2:18", "unexpected text inside <Node>; scene content goes in attributes"},
    {"TextOutsideTheRootElementIsReported", R"(<Node name="root"/>
  oops)",
     "inline.xml:2:3", "malformed XML: text outside the root element"},
    {"TextBeforeTheRootElementIsReported", R"(scene: <Node name="root"/>)", "inline.xml:1:1",
     "malformed XML: text outside the root element"},
    {"RepeatedAttributeIsReportedAtTheSecondOne", R"(<Node name="root" name="again"/>)", "inline.xml:1:19",
     "malformed XML: attribute 'name' is given twice in <Node> (first at line 1, column 7)"},
    {"UnclosedCommentIsReportedAtItsStart", R"(<Node name="root">
  <!-- note
</Node>)",
     "inline.xml:2:3", "malformed XML: comment is not closed with '-->'"},
    {"EmptyFileHasNoRootElement", "", "inline.xml:1:1", "malformed XML: the file has no root element"},
    {"CommentOnlyFileHasNoRootElement", "<!-- nothing -->\n", "inline.xml:1:1",
     "malformed XML: the file has no root element"},
    {"NulByteIsReportedWhereItIs", std::string("<Node name=\"root\">\n  ") + '\0' + "</Node>", "inline.xml:2:3",
     "malformed XML: NUL byte in the file"},
    {"InvalidElementNameIsReportedAtTheName", R"(<Node name="root"><1st/></Node>)", "inline.xml:1:20",
     "malformed XML: '1st' is not a valid element name"},
    {"EndTagWithoutANameIsReported", R"(<Node name="root"></ Node>)", "inline.xml:1:21",
     "malformed XML: expected an element name right after '</'"},
};

class XmlSyntaxErrorTest : public ::testing::TestWithParam<LocatedErrorCase> {};

TEST_P(XmlSyntaxErrorTest, TheFirstMistakeIsTheOneErrorAndSaysWhereItIs) {
  const LocatedErrorCase& c = GetParam();
  const Diagnostics d = loadFailure(c.xml, {}, c.fileName);
  EXPECT_TRUE(hasError(d, c.location, c.message));
  EXPECT_EQ(d.errorCount(), 1) << messages(d);
}

INSTANTIATE_TEST_SUITE_P(Syntax, XmlSyntaxErrorTest, ::testing::ValuesIn(kCases), caseName);

TEST(XmlSyntaxTest, TextAfterBlankLinesIsReportedWhereItStarts) {
  const Diagnostics d = loadFailure(R"(<Node name="root">

    stray words
  <Node name="a">more</Node>
  <![CDATA[ data ]]>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:3:5", "unexpected text inside <Node>"));
  EXPECT_TRUE(hasError(d, "inline.xml:4:18", "unexpected text inside <Node>"));
  EXPECT_TRUE(hasError(d, "inline.xml:5:3", "unexpected text inside <Node>"));
  EXPECT_EQ(d.errorCount(), 3);
}

TEST(XmlSyntaxTest, CommentsBlankCdataAndDeclarationsAreAllowed) {
  Diagnostics d;
  auto simulation = loadScene(R"(<?xml version="1.0" encoding="UTF-8"?>
<!DOCTYPE scene [ <!ENTITY unit "mm"> ]>
<!-- a comment with <Tags> inside -->
<Node name="root" units="mm">
  <!-- <Recordr/> commented out -->
  <![CDATA[   ]]>
</Node>
<!-- trailing comment -->
)",
                              d);
  EXPECT_NE(simulation, nullptr) << messages(d);
}

}  // namespace
}  // namespace trephine::test
