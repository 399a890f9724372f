// Where a diagnostic points: lines and columns are 1-based and count
// characters as written in the file (a UTF-8 sequence, a tab or an entity
// reference's every character counts as written, a byte order mark not at all).
// An element error points at '<', an attribute-name error at the name, a value
// error at the first character inside the quotes.
#include <gtest/gtest.h>

#include "tests/framework/scene/LoaderAssertions.h"

namespace trephine::test {
namespace {

const LocatedErrorCase kCases[] = {
    {"TabCountsAsOneColumn", "<Node name=\"root\">\n\t<Recordr/>\n</Node>", "inline.xml:2:2",
     "unknown component 'Recordr'"},
    {"TabsBetweenAttributesCountAsOneColumnEach", "<Node name=\"root\">\n\t<Recorder\tname=\"r\"\trat=\"1\"/>\n</Node>",
     "inline.xml:2:21", "unknown attribute 'rat' of Recorder 'r'"},
    {"MultibyteCharactersCountAsOneColumn",
     "<Node name=\"root\">\n  <Recorder name=\"r\" file=\"résumé.csv\" rat=\"1\"/>\n</Node>", "inline.xml:2:40",
     "unknown attribute 'rat'"},
    {"ValueErrorAfterMultibyteCharactersPointsInsideTheQuotes",
     "<Node name=\"root\">\n  <Recorder name=\"r\" file=\"résumé.csv\" rate=\"0\"/>\n</Node>", "inline.xml:2:46",
     "invalid rate of Recorder 'r': value 0 is out of range"},
    {"EntityReferencesCountAsWrittenNotAsDecoded",
     "<Node name=\"root\">\n  <Recorder file=\"&lt;x&gt;\" rat=\"1\"/>\n</Node>", "inline.xml:2:30",
     "unknown attribute 'rat'"},
    {"SingleQuotesAndSpacesAroundTheEqualsSign", "<Node name=\"root\">\n  <Recorder name = 'r' rate = '0'/>\n</Node>",
     "inline.xml:2:32", "invalid rate of Recorder 'r'"},
    {"AttributeOnAContinuationLineHasItsOwnLine",
     "<Node name=\"root\">\n  <Recorder name=\"r\"\n            rate=\"-5\"/>\n</Node>", "inline.xml:3:19",
     "invalid rate of Recorder 'r'"},
    {"CarriageReturnLineFeedEndsALine", "<Node name=\"root\">\r\n  <Recordr/>\r\n</Node>\r\n", "inline.xml:2:3",
     "unknown component 'Recordr'"},
    {"ByteOrderMarkTakesNoColumn", "\xEF\xBB\xBF<Node name=\"root\"><Recordr/></Node>", "inline.xml:1:19",
     "unknown component 'Recordr'"},
    {"MessagesUseTheGivenFileName", "<Node name=\"root\"><Recordr/></Node>", "scenes/mine.xml:1:19",
     "unknown component 'Recordr'", "scenes/mine.xml"},
};

class ColumnConventionTest : public ::testing::TestWithParam<LocatedErrorCase> {};

TEST_P(ColumnConventionTest, TheErrorStartsAtItsLineAndColumn) {
  const LocatedErrorCase& c = GetParam();
  EXPECT_TRUE(hasError(loadFailure(c.xml, {}, c.fileName), c.location, c.message)) << c.xml;
}

INSTANTIATE_TEST_SUITE_P(Columns, ColumnConventionTest, ::testing::ValuesIn(kCases), caseName);

}  // namespace
}  // namespace trephine::test
