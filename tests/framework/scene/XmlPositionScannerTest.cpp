// The scanner behind every column in loader messages.
#include <gtest/gtest.h>

#include <string>

#include "framework/scene/XmlPositionScanner.h"

namespace trephine {
namespace {

void expectAt(TextPosition actual, int line, int column) {
  EXPECT_EQ(actual.line, line);
  EXPECT_EQ(actual.column, column);
}

std::string problemOf(std::string_view text) {
  const ScanResult scan = scanXmlPositions(text);
  return scan.problem ? std::to_string(scan.problem->at.line) + ":" + std::to_string(scan.problem->at.column) + " " +
                            scan.problem->message
                      : "none";
}

TEST(XmlPositionScannerTest, RecordsElementsInDocumentOrderAtTheirOpeningBracket) {
  const ScanResult scan = scanXmlPositions("<a>\n  <b/>\n  <c><d/></c>\n</a>");
  ASSERT_FALSE(scan.problem) << scan.problem->message;
  ASSERT_EQ(scan.elements.size(), 4u);
  EXPECT_EQ(scan.elements[0].tag, "a");
  EXPECT_EQ(scan.elements[1].tag, "b");
  EXPECT_EQ(scan.elements[2].tag, "c");
  EXPECT_EQ(scan.elements[3].tag, "d");
  expectAt(scan.elements[0].at, 1, 1);
  expectAt(scan.elements[1].at, 2, 3);
  expectAt(scan.elements[2].at, 3, 3);
  expectAt(scan.elements[3].at, 3, 6);
}

TEST(XmlPositionScannerTest, RecordsAttributeNameAndFirstCharacterInsideTheQuotes) {
  const ScanResult scan = scanXmlPositions("<a x=\"1\" y = '22'\n   z=\"\"/>");
  ASSERT_FALSE(scan.problem);
  const auto& attributes = scan.elements.at(0).attributes;
  ASSERT_EQ(attributes.size(), 3u);
  EXPECT_EQ(attributes[0].name, "x");
  expectAt(attributes[0].nameAt, 1, 4);
  expectAt(attributes[0].valueAt, 1, 7);
  EXPECT_EQ(attributes[1].name, "y");
  expectAt(attributes[1].nameAt, 1, 10);
  expectAt(attributes[1].valueAt, 1, 15);
  EXPECT_EQ(attributes[2].name, "z");
  expectAt(attributes[2].nameAt, 2, 4);
  expectAt(attributes[2].valueAt, 2, 7);  // an empty value: where it would start
}

TEST(XmlPositionScannerTest, CountsCharactersNotBytesAndATabAsOne) {
  const ScanResult scan = scanXmlPositions("<a x=\"ééé\"\ty=\"→\" z=\"1\"/>");
  ASSERT_FALSE(scan.problem);
  const auto& attributes = scan.elements.at(0).attributes;
  expectAt(attributes[1].nameAt, 1, 12);
  expectAt(attributes[2].nameAt, 1, 18);
}

TEST(XmlPositionScannerTest, ValueMayContainGreaterThanAndTheOtherQuote) {
  const ScanResult scan = scanXmlPositions("<a x=\"1 > 0 's'\" y='\"'/>");
  ASSERT_FALSE(scan.problem) << scan.problem->message;
  ASSERT_EQ(scan.elements.at(0).attributes.size(), 2u);
  expectAt(scan.elements[0].attributes[1].nameAt, 1, 18);
}

TEST(XmlPositionScannerTest, SkipsCommentsCdataProcessingInstructionsAndDoctype) {
  const ScanResult scan = scanXmlPositions(
      "<?xml version=\"1.0\"?>\n<!DOCTYPE a [<!ELEMENT a ANY>]>\n<!-- <x/> -->\n<a><![CDATA[<y/>]]><b/></a>");
  ASSERT_FALSE(scan.problem) << scan.problem->message;
  ASSERT_EQ(scan.elements.size(), 2u);
  EXPECT_EQ(scan.elements[1].tag, "b");
  expectAt(scan.elements[1].at, 4, 20);
}

TEST(XmlPositionScannerTest, RecordsEachRunOfTextAtItsFirstNonBlankCharacter) {
  const ScanResult scan = scanXmlPositions("<a>\n  hello <!-- c --> world<![CDATA[ x ]]><![CDATA[  ]]></a>");
  ASSERT_FALSE(scan.problem);
  ASSERT_EQ(scan.texts.size(), 3u);
  expectAt(scan.texts[0], 2, 3);
  expectAt(scan.texts[1], 2, 20);
  expectAt(scan.texts[2], 2, 25);
}

TEST(XmlPositionScannerTest, ByteOrderMarkIsSkippedWithoutAColumn) {
  const ScanResult scan = scanXmlPositions("\xEF\xBB\xBF<a/>");
  ASSERT_FALSE(scan.problem);
  expectAt(scan.elements.at(0).at, 1, 1);
}

TEST(XmlPositionScannerTest, ReportsTheFirstWellFormednessProblemWithItsPosition) {
  EXPECT_EQ(problemOf("<a>\n<b></c>\n</a>"), "2:4 end tag </c> does not match <b> opened at line 2, column 1");
  EXPECT_EQ(problemOf("<a></a></b>"), "1:8 end tag </b> has no matching start tag");
  EXPECT_EQ(problemOf("<a>\n  <b>\n</a>"), "3:1 end tag </a> does not match <b> opened at line 2, column 3");
  EXPECT_EQ(problemOf("<a>\n  <b/>"), "1:1 element <a> is never closed");
  EXPECT_EQ(problemOf("<a x=\"1\""), "1:1 start tag <a> is not closed with '>'");
  EXPECT_EQ(problemOf("<a x=\"1/>\n</a>"),
            "1:7 value of attribute 'x' is not closed before the '<' at line 2, column 1 (a value cannot contain '<'; "
            "write &lt;)");
  EXPECT_EQ(problemOf("<a x=\"1"), "1:7 value of attribute 'x' is not closed");
  EXPECT_EQ(problemOf("<a x \"1\"/>"), "1:6 expected '=' after attribute 'x'");
  EXPECT_EQ(problemOf("<a x=1/>"), "1:6 expected a quoted value for attribute 'x'");
  EXPECT_EQ(problemOf("<a x=\"1\" x=\"2\"/>"), "1:10 attribute 'x' is given twice in <a> (first at line 1, column 4)");
  EXPECT_EQ(problemOf("<a/ >"), "1:3 unexpected '/' in <a>");
  EXPECT_EQ(problemOf("< a/>"), "1:2 expected an element name after '<'");
  EXPECT_EQ(problemOf("<a><-b/></a>"), "1:5 '-b' is not a valid element name (names start with a letter or '_')");
  EXPECT_EQ(problemOf("<a 9x=\"1\"/>"), "1:4 '9x' is not a valid attribute name (names start with a letter or '_')");
  EXPECT_EQ(problemOf("<a></a x>"), "1:8 expected '>' to close </a>");
  EXPECT_EQ(problemOf("<a><!-- x </a>"), "1:4 comment is not closed with '-->'");
  EXPECT_EQ(problemOf("<a><![CDATA[ x </a>"), "1:4 CDATA section is not closed with ']]>'");
  EXPECT_EQ(problemOf("<a><!--></a>"), "1:4 comment is not closed with '-->'");
  EXPECT_EQ(problemOf("<a><!-- --set x --></a>"),
            "1:9 '--' inside a comment: XML allows it only in the comment's end '-->' (write a single '-', or '- -')");
  EXPECT_EQ(problemOf("<a><!-- x ---></a>"),
            "1:11 '--' inside a comment: XML allows it only in the comment's end '-->' (write a single '-', or '- -')");
  EXPECT_EQ(problemOf("<a><!-- a - b --></a>"), "none");
  EXPECT_EQ(problemOf("<a><?></a>"), "1:4 processing instruction is not closed with '?>'");
  EXPECT_EQ(problemOf("<?xml version=\"1.0\""), "1:1 processing instruction is not closed with '?>'");
  EXPECT_EQ(problemOf("<!DOCTYPE a [ <!ELEMENT a ANY> "), "1:1 declaration is not closed with '>'");
}

TEST(XmlPositionScannerTest, RejectsWhatTheXmlLibraryWouldIgnoreOrMisplace) {
  EXPECT_EQ(problemOf("text <a/>"), "1:1 text outside the root element");
  EXPECT_EQ(problemOf("<a/>\n\n  x"), "3:3 text outside the root element");
  EXPECT_EQ(problemOf("<![CDATA[x]]><a/>"), "1:1 CDATA section outside the root element");
  EXPECT_EQ(problemOf("<a/></a>"), "1:5 end tag </a> has no matching start tag");
  EXPECT_EQ(problemOf("<a><?pi x?></a>"),
            "1:4 '<?...?>' is only allowed at the start of the file, before any other markup");
  EXPECT_EQ(problemOf("<!-- c --><?xml version=\"1.0\"?><a/>"),
            "1:11 '<?...?>' is only allowed at the start of the file, before any other markup");
  EXPECT_EQ(problemOf("<a><!DOCTYPE a></a>"), "1:4 '<!...>' declarations are only allowed before the root element");
  EXPECT_EQ(problemOf(std::string("<a>\n ") + '\0' + "</a>"), "2:2 NUL byte in the file (is it a text file?)");
  EXPECT_EQ(problemOf(""), "1:1 the file has no root element");
  EXPECT_EQ(problemOf("  \n<!-- -->\n"), "1:1 the file has no root element");
}

TEST(XmlPositionScannerTest, LimitsNestingDepthWithThePositionOfTheTooDeepElement) {
  const auto nested = [](int depth) {
    std::string text;
    for (int i = 0; i < depth; ++i) text += "<a>";
    for (int i = 0; i < depth; ++i) text += "</a>";
    return text;
  };
  EXPECT_EQ(problemOf(nested(64)), "none");
  EXPECT_EQ(problemOf(nested(65)), "1:193 elements nested more than 64 deep");
}

// An element of a thousand attributes is scanned; one more is refused at the
// attribute that goes over, before the XML library (whose cost grows with
// the square of an element's attributes: 100,000 of them took 100 s) sees
// it. Duplicates among a thousand are found by name, not by comparing each
// with every one before.
TEST(XmlPositionScannerTest, LimitsAttributesOfAnElementAndFindsDuplicatesAmongMany) {
  const auto element = [](int attributes, bool repeatFirst) {
    std::string text = "<a";
    for (int i = 0; i < attributes; ++i) text += " b" + std::to_string(i) + "=\"1\"";
    if (repeatFirst) text += " b0=\"2\"";
    return text + "/>";
  };
  EXPECT_EQ(problemOf(element(1000, false)), "none");
  const std::string tooMany = element(1001, false);
  const std::string problem = problemOf(tooMany);
  EXPECT_NE(problem.find("<a> has more than 1000 attributes"), std::string::npos) << problem;
  EXPECT_TRUE(problem.starts_with("1:" + std::to_string(tooMany.find(" b1000=") + 2))) << problem;
  EXPECT_NE(problemOf(element(999, true)).find("attribute 'b0' is given twice in <a> (first at line 1, column 4)"),
            std::string::npos);
}

TEST(XmlPositionScannerTest, AcceptsAWellFormedScene) {
  EXPECT_EQ(problemOf("<?xml version=\"1.0\"?>\r\n<Node name=\"root\">\r\n  <Recorder name='r'/>\r\n</Node>\r\n"),
            "none");
}

TEST(XmlPositionScannerTest, SurvivesTruncationAtEveryByte) {
  const std::string scene = "<?xml version=\"1.0\"?><!-- c --><a x=\"1\" y='2'><b><![CDATA[z]]></b>text</a>";
  for (size_t n = 0; n <= scene.size(); ++n) {
    const ScanResult scan = scanXmlPositions(std::string_view(scene).substr(0, n));
    EXPECT_EQ(scan.problem.has_value(), n < scene.size()) << "truncated to " << n << " bytes";
  }
}

}  // namespace
}  // namespace trephine
