#include "framework/formats/volume/VolumeWriter.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "framework/core/Strings.h"

namespace trephine::formats {

namespace {

constexpr size_t kChunkVoxels = size_t(1) << 20;

bool isExact(const DensityEncoding& encoding) { return encoding.scale == 1 && encoding.offset == 0; }

template <typename T>
void appendLittleEndian(T value, std::vector<uint8_t>& out) {
  auto bits = std::bit_cast<std::conditional_t<sizeof(T) == 2, uint16_t, uint32_t>>(value);
  for (size_t b = 0; b < sizeof bits; ++b) out.push_back(uint8_t(bits >> (8 * b)));
}

// Hands the little-endian samples of `volume` to `sink` a chunk at a time, so
// no second copy of the volume is made.
void forEachSampleChunk(const DensityVolume& volume, const std::function<void(std::span<const uint8_t>)>& sink) {
  const bool exact = isExact(volume.encoding());
  std::vector<uint8_t> chunk;
  for (size_t begin = 0; begin < volume.voxelCount(); begin += kChunkVoxels) {
    const size_t end = std::min(volume.voxelCount(), begin + kChunkVoxels);
    chunk.clear();
    for (size_t n = begin; n < end; ++n) {
      if (exact) {
        appendLittleEndian<int16_t>(volume.code(n), chunk);
      } else {
        appendLittleEndian<float>(static_cast<float>(volume.encoding().density(volume.code(n))), chunk);
      }
    }
    sink(chunk);
  }
}

std::vector<uint8_t> compressedSamples(const DensityVolume& volume, const std::filesystem::path& file) {
  z_stream z{};
  if (deflateInit(&z, Z_DEFAULT_COMPRESSION) != Z_OK) throw VolumeWriteError(file, "cannot initialise zlib");
  std::vector<uint8_t> out;
  std::vector<uint8_t> buffer(size_t(1) << 16);
  const auto pump = [&](std::span<const uint8_t> input, int flush) {
    z.next_in = const_cast<Bytef*>(input.data());
    z.avail_in = static_cast<uInt>(input.size());
    int code = Z_OK;
    do {
      z.next_out = buffer.data();
      z.avail_out = static_cast<uInt>(buffer.size());
      code = deflate(&z, flush);
      if (code == Z_STREAM_ERROR) {
        deflateEnd(&z);
        throw VolumeWriteError(file, "zlib compression failed");
      }
      out.insert(out.end(), buffer.data(), buffer.data() + (buffer.size() - z.avail_out));
    } while (z.avail_out == 0 || (flush == Z_FINISH && code != Z_STREAM_END));
  };
  forEachSampleChunk(volume, [&](std::span<const uint8_t> chunk) { pump(chunk, Z_NO_FLUSH); });
  pump({}, Z_FINISH);
  deflateEnd(&z);
  return out;
}

std::string headerText(const DensityVolume& volume, bool compressed, uint64_t compressedBytes,
                       const std::string& dataFile) {
  const auto three = [](const auto& v) {
    return formatDouble(double(v[0])) + " " + formatDouble(double(v[1])) + " " + formatDouble(double(v[2]));
  };
  std::string text;
  text += "ObjectType = Image\n";
  text += "NDims = 3\n";
  text += "BinaryData = True\n";
  text += "BinaryDataByteOrderMSB = False\n";
  text += std::string("CompressedData = ") + (compressed ? "True" : "False") + "\n";
  if (compressed) text += "CompressedDataSize = " + std::to_string(compressedBytes) + "\n";
  text += "TransformMatrix = 1 0 0 0 1 0 0 0 1\n";
  text += "Offset = " + three(volume.origin()) + "\n";
  text += "CenterOfRotation = 0 0 0\n";
  text += "ElementSpacing = " + three(volume.spacing()) + "\n";
  text += "DimSize = " + three(volume.dims()) + "\n";
  text += std::string("ElementType = ") + (isExact(volume.encoding()) ? "MET_SHORT" : "MET_FLOAT") + "\n";
  text += "ElementDataFile = " + dataFile + "\n";
  return text;
}

}  // namespace

void writeMetaImage(const DensityVolume& volume, const OutputPath& output, bool compress) {
  const std::filesystem::path file = output.path();
  const std::string extension = file.extension().string();
  const bool local = extension == ".mha";
  if (!local && extension != ".mhd")
    throw VolumeWriteError(file, "unknown extension '" + extension + "' (expected .mha or .mhd)");
  if (volume.voxelCount() == 0) throw VolumeWriteError(file, "the volume is empty");

  std::vector<uint8_t> compressed;
  if (compress) compressed = compressedSamples(volume, file);
  const auto writeSamples = [&](AtomicFile& out) {
    if (compress) {
      out.write(compressed);
    } else {
      forEachSampleChunk(volume, [&](std::span<const uint8_t> chunk) { out.write(chunk); });
    }
  };

  if (local) {
    AtomicFile out(output);
    out.write(headerText(volume, compress, compressed.size(), "LOCAL"));
    writeSamples(out);
    out.commit();
    return;
  }
  const std::filesystem::path dataFile = file.stem().string() + (compress ? ".zraw" : ".raw");
  {
    AtomicFile data(output.beside(dataFile.string()));
    writeSamples(data);
    data.commit();
  }
  AtomicFile header(output);
  header.write(headerText(volume, compress, compressed.size(), dataFile.string()));
  header.commit();
}

}  // namespace trephine::formats
