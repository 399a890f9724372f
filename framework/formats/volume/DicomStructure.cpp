#include "framework/formats/volume/DicomStructure.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

namespace {

constexpr uint32_t kUndefined = 0xFFFFFFFFu;
constexpr int kMaxDepth = 32;

constexpr std::array<std::string_view, 34> kVrs = {"AE", "AS", "AT", "CS", "DA", "DS", "DT", "FL", "FD",
                                                   "IS", "LO", "LT", "OB", "OD", "OF", "OL", "OV", "OW",
                                                   "PN", "SH", "SL", "SQ", "SS", "ST", "SV", "TM", "UC",
                                                   "UI", "UL", "UN", "UR", "US", "UT", "UV"};
// VRs whose explicit form has 2 reserved bytes and a 32-bit length.
constexpr std::array<std::string_view, 13> kLongVrs = {"OB", "OD", "OF", "OL", "OV", "OW", "SQ",
                                                       "SV", "UC", "UN", "UR", "UT", "UV"};

class Walker {
 public:
  Walker(const std::filesystem::path& file, std::span<const uint8_t> bytes) : m_file(file), m_bytes(bytes) {}

  [[noreturn]] void fail(uint64_t at, const std::string& problem) const {
    throw VolumeReadError(m_file, "not a well-formed DICOM file at byte " + std::to_string(at) + ": " + problem);
  }

  uint16_t u16(uint64_t at) const {
    if (at + 2 > m_bytes.size()) fail(at, "the file ends inside an element header");
    return uint16_t(m_bytes[at] | (m_bytes[at + 1] << 8));
  }
  uint32_t u32(uint64_t at) const {
    if (at + 4 > m_bytes.size()) fail(at, "the file ends inside an element header");
    return uint32_t(m_bytes[at]) | (uint32_t(m_bytes[at + 1]) << 8) | (uint32_t(m_bytes[at + 2]) << 16) |
           (uint32_t(m_bytes[at + 3]) << 24);
  }

  struct Header {
    uint16_t group = 0, element = 0;
    std::string vr;  // empty in implicit VR
    uint32_t length = 0;
    uint64_t value = 0;  // offset of the value
  };

  Header header(uint64_t at, bool explicitVr) const {
    Header h;
    h.group = u16(at);
    h.element = u16(at + 2);
    // Item and delimiter tags have no VR in either syntax.
    if (!explicitVr || h.group == 0xFFFE) {
      h.length = u32(at + 4);
      h.value = at + 8;
      return h;
    }
    if (at + 6 > m_bytes.size()) fail(at, "the file ends inside an element header");
    h.vr.assign(reinterpret_cast<const char*>(m_bytes.data() + at + 4), 2);
    if (std::find(kVrs.begin(), kVrs.end(), h.vr) == kVrs.end())
      fail(at, "an unknown value representation for (" + hex(h.group) + "," + hex(h.element) + ")");
    if (std::find(kLongVrs.begin(), kLongVrs.end(), h.vr) != kLongVrs.end()) {
      h.length = u32(at + 8);
      h.value = at + 12;
    } else {
      h.length = u16(at + 6);
      h.value = at + 8;
    }
    return h;
  }

  static std::string hex(uint16_t v) {
    char text[8];
    std::snprintf(text, sizeof text, "%04X", v);
    return text;
  }

  // Walks elements from `at` to `end` (or, with `untilDelimiter`, to the
  // delimiter that closes them); returns the offset after the last one.
  uint64_t elements(uint64_t at, uint64_t end, bool explicitVr, int depth, uint16_t delimiter) {
    if (depth > kMaxDepth) fail(at, "sequences nested deeper than " + std::to_string(kMaxDepth));
    while (at < end) {
      // Zeros to the end of the file after the top-level data set (a tag
      // (0000,0000) cannot start an element there): padding, not an element.
      if (depth == 0 && delimiter == 0 && allZeros(at, end)) {
        m_pixel.trailingZeros = end - at;
        return end;
      }
      const Header h = header(at, explicitVr);
      if (h.group == 0xFFFE) {
        if (h.element == delimiter && delimiter != 0) {
          if (h.length != 0) fail(at, "a delimiter with a length");
          return h.value;
        }
        fail(at, "an item or delimiter tag out of place");
      }
      if (explicitVr) checkTypedVr(h, at);
      if (depth == 0) checkImageAttribute(h, at);
      if (h.group == 0x0028 && h.element == 0x1053) checkRescaleSlope(h, at);
      if (depth == 0 && h.group == 0x0028 && h.element == 0x1052) m_interceptAt = at;
      if (depth == 0 && h.group == 0x0028 && h.element == 0x1053) m_hasSlope = true;
      at = value(h, at, end, explicitVr, depth);
    }
    if (delimiter != 0) fail(at, "a sequence or item of undefined length is not closed");
    if (at != end) fail(at, "an element runs past its parent's end");
    return at;
  }

  bool allZeros(uint64_t from, uint64_t end) const {
    if (from + 4 > end) return false;  // an element header needs more
    return std::all_of(m_bytes.begin() + std::ptrdiff_t(from), m_bytes.begin() + std::ptrdiff_t(end),
                       [](uint8_t b) { return b == 0; });
  }

  std::string text(const Header& h) const {
    std::string t(reinterpret_cast<const char*>(m_bytes.data() + h.value), h.length);
    while (!t.empty() && (t.back() == '\0' || t.back() == ' ')) t.pop_back();
    return t;
  }

  // The elements GDCM reads through gdcm::Attribute (its image helper and
  // pixel reader), with their standard VR: Attribute asserts that a stored
  // VR is compatible with the dictionary's.
  void checkTypedVr(const Header& h, uint64_t at) const {
    struct Typed {
      uint16_t group, element;
      const char* vr;
    };
    static constexpr Typed kTyped[] = {
        {0x0018, 0x0050, "DS"}, {0x0018, 0x0088, "DS"}, {0x0020, 0x0032, "DS"}, {0x0020, 0x0037, "DS"},
        {0x0028, 0x0002, "US"}, {0x0028, 0x0004, "CS"}, {0x0028, 0x0006, "US"}, {0x0028, 0x0008, "IS"},
        {0x0028, 0x0010, "US"}, {0x0028, 0x0011, "US"}, {0x0028, 0x0030, "DS"}, {0x0028, 0x0100, "US"},
        {0x0028, 0x0101, "US"}, {0x0028, 0x0102, "US"}, {0x0028, 0x0103, "US"}, {0x0028, 0x1052, "DS"},
        {0x0028, 0x1053, "DS"}, {0x0028, 0x2110, "CS"}, {0x0008, 0x0016, "UI"}, {0x0020, 0x000E, "UI"},
        {0x0008, 0x103E, "LO"}, {0x0028, 0x9110, "SQ"}, {0x0020, 0x9113, "SQ"}, {0x0020, 0x9116, "SQ"},
        {0x0028, 0x9145, "SQ"}, {0x5200, 0x9229, "SQ"}, {0x5200, 0x9230, "SQ"}};
    for (const Typed& t : kTyped)
      if (h.group == t.group && h.element == t.element && h.vr != t.vr)
        fail(at, "(" + hex(h.group) + "," + hex(h.element) + ") has value representation " + h.vr + " (expected " +
                     t.vr + ")");
  }

  // RescaleSlope (0028,1053), at any depth (an enhanced image's functional
  // groups carry it too): GDCM asserts that the slope it reads is not zero,
  // and reads text that is not a number as zero.
  void checkRescaleSlope(const Header& h, uint64_t at) const {
    if (h.length == kUndefined || h.value + h.length > m_bytes.size()) return;  // the walk reports it
    std::string first = text(h);
    first = first.substr(0, first.find('\\'));
    const size_t start = first.find_first_not_of(' ');
    const char* begin = first.c_str() + (start == std::string::npos ? first.size() : start);
    char* end = nullptr;
    const double slope = std::strtod(begin, &end);
    if (end == begin || !(slope != 0))
      fail(at, "RescaleSlope (0028,1053) is \"" + first.substr(0, 32) + "\" (expected a number other than 0)");
  }

  // The image storage classes read (CT, MR and their enhanced forms,
  // secondary captures); GDCM's reader asserts on some files of classes it
  // does not know.
  void checkSopClass(const std::string& uid, uint64_t at) const {
    static constexpr std::array<std::string_view, 8> kClasses = {
        "1.2.840.10008.5.1.4.1.1.2",   "1.2.840.10008.5.1.4.1.1.2.1", "1.2.840.10008.5.1.4.1.1.4",
        "1.2.840.10008.5.1.4.1.1.4.1", "1.2.840.10008.5.1.4.1.1.7",   "1.2.840.10008.5.1.4.1.1.7.2",
        "1.2.840.10008.5.1.4.1.1.7.3", "1.2.840.10008.5.1.4.1.1.7.4"};
    if (uid == "1.2.840.10008.5.1.4.1.1.66.4")
      fail(at, "a DICOM Segmentation (SEG, SOP class " + uid +
                   ") is not read: convert it to a labelmap volume (dcmqi's segimage2itkimage writes NRRD)");
    if (std::find(kClasses.begin(), kClasses.end(), uid) == kClasses.end())
      fail(at, "SOP class " + uid + " (expected a CT, MR or secondary capture image)");
  }

  // The Image Pixel attributes GDCM asserts on rather than refuses: each
  // in the range the standard allows (PS3.3 C.7.6.3).
  void checkImageAttribute(const Header& h, uint64_t at) {
    if (h.length == kUndefined) return;
    if (h.group == 0x0008 && h.element == 0x0016) {
      if (h.value + h.length > m_bytes.size()) fail(at, "the SOP class runs past the end of the file");
      checkSopClass(text(h), at);
    }
    if (h.group == 0x0008 && h.element == 0x0010) fail(at, "an ACR-NEMA Recognition Code (0008,0010): not read");
    if (h.group != 0x0028) return;
    if (h.element == 0x0004) {
      if (h.value + h.length > m_bytes.size()) fail(at, "(0028,0004) runs past the end of the file");
      m_pixel.photometricInterpretation = text(h);
      const std::string& pi = m_pixel.photometricInterpretation;
      if (pi != "MONOCHROME2" && pi != "MONOCHROME1")
        fail(at, "PhotometricInterpretation (0028,0004) is \"" + pi.substr(0, 32) +
                     "\" (expected MONOCHROME2 or MONOCHROME1: a grey-level CT or MR image)");
      return;
    }
    const bool isUs = h.element == 0x0002 || h.element == 0x0100 || h.element == 0x0101 || h.element == 0x0102 ||
                      h.element == 0x0103 || h.element == 0x0010 || h.element == 0x0011;
    if (!isUs) return;
    if (h.length != 2) fail(at, "(0028," + hex(h.element) + ") is not one US value");
    const uint16_t v = u16(h.value);
    auto need = [&](bool ok, const std::string& what) {
      if (!ok) fail(at, "(0028," + hex(h.element) + ") is " + std::to_string(v) + " (expected " + what + ")");
    };
    switch (h.element) {
      case 0x0002: need(v == 1, "SamplesPerPixel 1: a grey-level image"); break;
      case 0x0100: need(v == 1 || v == 8 || v == 16 || v == 32 || v == 64, "BitsAllocated 1, 8, 16, 32 or 64"); break;
      case 0x0101: need(v >= 1 && v <= 64, "BitsStored 1 to 64"); m_bitsStored = v; break;
      case 0x0102: need(v < 64, "HighBit below 64"); m_highBit = v; break;
      case 0x0103: need(v <= 1, "PixelRepresentation 0 or 1"); m_pixel.pixelRepresentation = v; break;
      default: break;
    }
    if (h.element == 0x0100) m_bitsAllocated = v;
    if (m_bitsAllocated && m_bitsStored && m_bitsStored > m_bitsAllocated) fail(at, "BitsStored above BitsAllocated");
    if (m_bitsAllocated && m_highBit >= 0 && m_highBit >= m_bitsAllocated) fail(at, "HighBit at or above BitsAllocated");
  }

  // Past the value of `h` (at `at`), inside `end`.
  uint64_t value(const Header& h, uint64_t at, uint64_t end, bool explicitVr, int depth) {
    const bool isSequence = h.vr == "SQ" || (h.vr.empty() && h.length == kUndefined) ||
                            (h.vr == "UN" && h.length == kUndefined);
    const bool isPixelData = h.group == 0x7FE0 && h.element == 0x0010;
    if (h.length == kUndefined) {
      if (isPixelData) return fragments(h.value, end, depth);
      if (!isSequence) fail(at, "an undefined length on a (" + hex(h.group) + "," + hex(h.element) + ") " + h.vr);
      // UN of undefined length is encoded as implicit VR (PS3.5 6.2.2).
      return items(h.value, end, h.vr == "UN" ? false : explicitVr, depth, kUndefined);
    }
    if (h.value + h.length > end) fail(at, "a length of " + std::to_string(h.length) + " runs past its parent's end");
    if (h.vr == "SQ") items(h.value, h.value + h.length, explicitVr, depth, h.length);
    return h.value + h.length;
  }

  // The items of a sequence starting at `at`.
  uint64_t items(uint64_t at, uint64_t end, bool explicitVr, int depth, uint32_t length) {
    const uint64_t stop = length == kUndefined ? end : at + length;
    while (at < stop) {
      const Header h = header(at, false);
      if (h.group != 0xFFFE) fail(at, "a sequence holds something other than items");
      if (h.element == 0xE0DD) {
        if (length != kUndefined) fail(at, "a sequence delimiter in a sequence of defined length");
        return h.value;
      }
      if (h.element != 0xE000) fail(at, "an item delimiter outside an item");
      if (h.length == kUndefined) {
        at = elements(h.value, stop, explicitVr, depth + 1, 0xE00D);
      } else {
        if (h.value + h.length > stop) fail(at, "an item runs past its sequence's end");
        elements(h.value, h.value + h.length, explicitVr, depth + 1, 0);
        at = h.value + h.length;
      }
    }
    if (length == kUndefined) fail(at, "a sequence of undefined length is not closed");
    return at;
  }

  // Encapsulated pixel data: items (the offset table, then fragments) to the
  // sequence delimiter.
  uint64_t fragments(uint64_t at, uint64_t end, int depth) {
    while (at < end) {
      const Header h = header(at, false);
      if (h.group != 0xFFFE) fail(at, "encapsulated pixel data hold something other than items");
      if (h.element == 0xE0DD) return h.value;
      if (h.element != 0xE000 || h.length == kUndefined || h.value + h.length > end)
        fail(at, "a pixel data fragment of a bad length");
      at = h.value + h.length;
    }
    fail(at, "encapsulated pixel data are not closed");
  }

  // The transfer syntaxes read: uncompressed little endian, and the
  // compressed ones GDCM decodes (JPEG, JPEG-LS, JPEG 2000, RLE). GDCM's
  // meta reader falls back to a path that asserts when it does not know one.
  static bool isReadSyntax(const std::string& uid) {
    static constexpr std::array<std::string_view, 11> kSyntaxes = {
        "1.2.840.10008.1.2",      "1.2.840.10008.1.2.1",    "1.2.840.10008.1.2.4.50", "1.2.840.10008.1.2.4.51",
        "1.2.840.10008.1.2.4.57", "1.2.840.10008.1.2.4.70", "1.2.840.10008.1.2.4.80", "1.2.840.10008.1.2.4.81",
        "1.2.840.10008.1.2.4.90", "1.2.840.10008.1.2.4.91", "1.2.840.10008.1.2.5"};
    return std::find(kSyntaxes.begin(), kSyntaxes.end(), uid) != kSyntaxes.end();
  }

  // The value representations of the File Meta Information elements
  // (PS3.10 table 7.1-1).
  static bool isMetaVr(const std::string& vr) {
    return vr == "UL" || vr == "OB" || vr == "UI" || vr == "SH" || vr == "AE" || vr == "UR";
  }

  // GDCM reads the meta group strictly only while it is what PS3.10
  // describes; on anything else it retries with a lenient reader that
  // asserts on a short file or an unknown syntax. So the meta group must be:
  // (0002,0000) UL first, explicit VR elements of the meta VRs, exactly as
  // long as (0002,0000) says, a syntax read here, and a data set after it.
  DicomPixelAttributes walk() {
    if (m_bytes.size() < 132 || std::memcmp(m_bytes.data() + 128, "DICM", 4) != 0)
      fail(0, "no \"DICM\" after a 128-byte preamble");
    uint64_t at = 132;
    const Header first = header(at, true);
    if (first.group != 0x0002 || first.element != 0x0000 || first.vr != "UL" || first.length != 4)
      fail(at, "the meta information does not start with its Group Length (0002,0000), one UL");
    const uint64_t groupLength = u32(first.value);
    const uint64_t groupStart = first.value + 4;
    at = groupStart;
    std::string syntax;
    bool sawSopClass = false;
    while (at + 4 <= m_bytes.size() && u16(at) == 0x0002) {
      const Header h = header(at, true);
      if (!isMetaVr(h.vr))
        fail(at, "the meta element (0002," + hex(h.element) + ") has value representation " + h.vr +
                     " (expected UL, OB, UI, SH, AE or UR)");
      if (h.value + h.length > m_bytes.size()) fail(at, "a meta element runs past the end of the file");
      if (h.element == 0x0000) fail(at, "a second Group Length (0002,0000) in the meta information");
      if (h.element == 0x0010) syntax = text(h);
      if (h.element == 0x0002) checkSopClass(text(h), at), sawSopClass = true;
      at = h.value + h.length;
    }
    if (groupLength != at - groupStart)
      fail(groupStart, "File Meta Information Group Length (0002,0000) says " + std::to_string(groupLength) +
                           " bytes, the group holds " + std::to_string(at - groupStart));
    if (syntax.empty()) fail(at, "no Transfer Syntax UID (0002,0010) in the meta information");
    if (!sawSopClass) fail(at, "no Media Storage SOP Class UID (0002,0002) in the meta information");
    if (syntax == "1.2.840.10008.1.2.2") fail(at, "explicit VR big endian (retired) is not read");
    if (syntax == "1.2.840.10008.1.2.1.99") fail(at, "deflated data sets are not read");
    if (!isReadSyntax(syntax))
      fail(at, "transfer syntax " + syntax +
                   " (expected implicit or explicit VR little endian, JPEG, JPEG-LS, JPEG 2000 or RLE)");
    if (at >= m_bytes.size()) fail(at, "the file ends after its meta information, with no data set");
    elements(at, m_bytes.size(), syntax != "1.2.840.10008.1.2", 0, 0);
    m_pixel.dataSetEnd = m_bytes.size() - m_pixel.trailingZeros;
    // GDCM reads both when either is there, and takes an absent slope for 0.
    if (m_interceptAt && !m_hasSlope)
      fail(*m_interceptAt, "RescaleIntercept (0028,1052) without RescaleSlope (0028,1053)");
    // Zeros from the meta information on are not a padded data set but none
    // (and GDCM asserts on a file that ends after its meta information).
    if (m_pixel.dataSetEnd <= at) fail(at, "only zeros after the meta information, no data set");
    // Absent BitsStored and HighBit mean all the allocated bits.
    m_pixel.bitsAllocated = uint16_t(m_bitsAllocated);
    m_pixel.bitsStored = uint16_t(m_bitsStored > 0 ? m_bitsStored : m_bitsAllocated);
    m_pixel.highBit = uint16_t(m_highBit >= 0 ? m_highBit : std::max(int(m_pixel.bitsStored) - 1, 0));
    return m_pixel;
  }

 private:
  const std::filesystem::path& m_file;
  std::span<const uint8_t> m_bytes;
  int m_bitsAllocated = 0, m_bitsStored = 0, m_highBit = -1;
  std::optional<uint64_t> m_interceptAt;  // where a top-level RescaleIntercept is
  bool m_hasSlope = false;
  DicomPixelAttributes m_pixel;
};

}  // namespace

DicomPixelAttributes checkDicomStructure(const std::filesystem::path& file, std::span<const uint8_t> bytes) {
  return Walker(file, bytes).walk();
}

}  // namespace trephine::formats
