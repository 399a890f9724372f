// Malformed XML: one error at the first problem (the tree is not built from a
// broken file, so nothing else is reported), with the position of the mistake.
#include <gtest/gtest.h>

#include <string>

#include "tests/framework/scene/LoaderAssertions.h"

namespace trephine::test {
namespace {

TEST(XmlSyntaxErrorTest, MismatchedEndTagPointsAtTheEndTagAndNamesTheOpenElement) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder name="r"></Recordr>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:22",
                       "malformed XML: end tag </Recordr> does not match <Recorder> opened at line 2, column 3"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(XmlSyntaxErrorTest, UnclosedAttributeValueIsReportedAtTheValueWithWhereItRanInto) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder name="r/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:19",
                       "malformed XML: value of attribute 'name' is not closed before the '<' at line 3, column 1"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(XmlSyntaxErrorTest, AttributeValueUnclosedAtEndOfFile) {
  const Diagnostics d = loadFailure(R"(<Node name="root)");
  EXPECT_TRUE(hasError(d, "inline.xml:1:13", "malformed XML: value of attribute 'name' is not closed"));
}

TEST(XmlSyntaxErrorTest, MissingEqualsSignIsReportedWhereItWasExpected) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder name "r"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:18", "malformed XML: expected '=' after attribute 'name'"));
}

TEST(XmlSyntaxErrorTest, UnquotedValueIsReported) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder name=r/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:18", "malformed XML: expected a quoted value for attribute 'name'"));
}

TEST(XmlSyntaxErrorTest, ElementUnclosedAtEndOfFileIsReportedAtItsStart) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Node name="a"/>
)");
  EXPECT_TRUE(hasError(d, "inline.xml:1:1", "malformed XML: element <Node> is never closed"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(XmlSyntaxErrorTest, StartTagUnclosedAtEndOfFile) {
  const Diagnostics d = loadFailure(R"(<Node name="root")");
  EXPECT_TRUE(hasError(d, "inline.xml:1:1", "malformed XML: start tag <Node> is not closed with '>'"));
}

TEST(XmlSyntaxErrorTest, SecondRootElementIsReportedAtItsStart) {
  const Diagnostics d = loadFailure(R"(<Node name="root"/>
<Node name="two"/>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:1", "a scene file has one root element; found a second one <Node>"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(XmlSyntaxErrorTest, TextInsideAnElementIsReportedAtItsFirstCharacter) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Node name="a">hello</Node>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:18", "unexpected text inside <Node>; scene content goes in attributes"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(XmlSyntaxErrorTest, TextAfterBlankLinesIsReportedWhereItStarts) {
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

TEST(XmlSyntaxErrorTest, CommentsBlankCdataAndDeclarationsAreAllowed) {
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

TEST(XmlSyntaxErrorTest, TextOutsideTheRootElementIsReported) {
  const Diagnostics d = loadFailure(R"(<Node name="root"/>
  oops)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:3", "malformed XML: text outside the root element"));
}

TEST(XmlSyntaxErrorTest, TextBeforeTheRootElementIsReported) {
  const Diagnostics d = loadFailure(R"(scene: <Node name="root"/>)");
  EXPECT_TRUE(hasError(d, "inline.xml:1:1", "malformed XML: text outside the root element"));
}

TEST(XmlSyntaxErrorTest, RepeatedAttributeIsReportedAtTheSecondOne) {
  const Diagnostics d = loadFailure(R"(<Node name="root" name="again"/>)");
  EXPECT_TRUE(hasError(d, "inline.xml:1:19",
                       "malformed XML: attribute 'name' is given twice in <Node> (first at line 1, column 7)"));
}

TEST(XmlSyntaxErrorTest, UnclosedCommentIsReportedAtItsStart) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <!-- note
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:3", "malformed XML: comment is not closed with '-->'"));
}

TEST(XmlSyntaxErrorTest, EmptyFileHasNoRootElement) {
  const Diagnostics d = loadFailure("");
  EXPECT_TRUE(hasError(d, "inline.xml:1:1", "malformed XML: the file has no root element"));
}

TEST(XmlSyntaxErrorTest, CommentOnlyFileHasNoRootElement) {
  const Diagnostics d = loadFailure("<!-- nothing -->\n");
  EXPECT_TRUE(hasError(d, "inline.xml:1:1", "malformed XML: the file has no root element"));
}

TEST(XmlSyntaxErrorTest, NulByteIsReportedWhereItIs) {
  const Diagnostics d = loadFailure(std::string("<Node name=\"root\">\n  ") + '\0' + "</Node>");
  EXPECT_TRUE(hasError(d, "inline.xml:2:3", "malformed XML: NUL byte in the file"));
}

TEST(XmlSyntaxErrorTest, InvalidElementNameIsReportedAtTheName) {
  const Diagnostics d = loadFailure(R"(<Node name="root"><1st/></Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:1:20", "malformed XML: '1st' is not a valid element name"));
}

TEST(XmlSyntaxErrorTest, EndTagWithoutANameIsReported) {
  const Diagnostics d = loadFailure(R"(<Node name="root"></ Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:1:21", "malformed XML: expected an element name right after '</'"));
}

}  // namespace
}  // namespace trephine::test
