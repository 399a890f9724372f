// Where a diagnostic points: lines and columns are 1-based and count
// characters as written in the file (a UTF-8 sequence, a tab or an entity
// reference's every character counts as written, a byte order mark not at all).
// An element error points at '<', an attribute-name error at the name, a value
// error at the first character inside the quotes.
#include <gtest/gtest.h>

#include "tests/framework/scene/LoaderAssertions.h"

namespace trephine::test {
namespace {

TEST(ColumnConventionTest, TabCountsAsOneColumn) {
  const Diagnostics d = loadFailure("<Node name=\"root\">\n\t<Recordr/>\n</Node>");
  EXPECT_TRUE(hasError(d, "inline.xml:2:2", "unknown component 'Recordr'"));
}

TEST(ColumnConventionTest, TabsBetweenAttributesCountAsOneColumnEach) {
  const Diagnostics d = loadFailure("<Node name=\"root\">\n\t<Recorder\tname=\"r\"\trat=\"1\"/>\n</Node>");
  EXPECT_TRUE(hasError(d, "inline.xml:2:21", "unknown attribute 'rat' of Recorder 'r'"));
}

TEST(ColumnConventionTest, MultibyteCharactersCountAsOneColumn) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder name="r" file="résumé.csv" rat="1"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:40", "unknown attribute 'rat'"));
}

TEST(ColumnConventionTest, ValueErrorAfterMultibyteCharactersPointsInsideTheQuotes) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder name="r" file="résumé.csv" rate="0"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:46", "invalid rate of Recorder 'r': value 0 is out of range"));
}

TEST(ColumnConventionTest, EntityReferencesCountAsWrittenNotAsDecoded) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder file="&lt;x&gt;" rat="1"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:30", "unknown attribute 'rat'"));
}

TEST(ColumnConventionTest, SingleQuotesAndSpacesAroundTheEqualsSign) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder name = 'r' rate = '0'/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:32", "invalid rate of Recorder 'r'"));
}

TEST(ColumnConventionTest, AttributeOnAContinuationLineHasItsOwnLine) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder name="r"
            rate="-5"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:3:19", "invalid rate of Recorder 'r'"));
}

TEST(ColumnConventionTest, CarriageReturnLineFeedEndsALine) {
  const Diagnostics d = loadFailure("<Node name=\"root\">\r\n  <Recordr/>\r\n</Node>\r\n");
  EXPECT_TRUE(hasError(d, "inline.xml:2:3", "unknown component 'Recordr'"));
}

TEST(ColumnConventionTest, ByteOrderMarkTakesNoColumn) {
  const Diagnostics d = loadFailure("\xEF\xBB\xBF<Node name=\"root\"><Recordr/></Node>");
  EXPECT_TRUE(hasError(d, "inline.xml:1:19", "unknown component 'Recordr'"));
}

TEST(ColumnConventionTest, MessagesUseTheGivenFileName) {
  const Diagnostics d = loadFailure(R"(<Node name="root"><Recordr/></Node>)", {}, "scenes/mine.xml");
  EXPECT_TRUE(hasError(d, "scenes/mine.xml:1:19", "unknown component 'Recordr'"));
}

}  // namespace
}  // namespace trephine::test
