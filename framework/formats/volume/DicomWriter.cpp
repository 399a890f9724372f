#include "framework/formats/volume/DicomWriter.h"

#include <gdcmAttribute.h>
#include <gdcmImageWriter.h>
#include <gdcmTrace.h>
#include <gdcmUIDGenerator.h>

#include <cstdio>
#include <system_error>
#include <vector>

namespace trephine::formats {

namespace fs = std::filesystem;

namespace {

void writeSlice(const DensityVolume& volume, int32_t k, const fs::path& file, const std::string& seriesUid,
                const std::string& studyUid, const std::string& description) {
  const auto& d = volume.dims();
  gdcm::ImageWriter writer;
  gdcm::Image& image = writer.GetImage();
  image.SetNumberOfDimensions(2);
  image.SetDimension(0, unsigned(d[0]));
  image.SetDimension(1, unsigned(d[1]));
  image.SetPixelFormat(gdcm::PixelFormat::INT16);
  image.SetPhotometricInterpretation(gdcm::PhotometricInterpretation::MONOCHROME2);
  image.SetSpacing(0, volume.spacing().x());
  image.SetSpacing(1, volume.spacing().y());
  const Vec3 origin = volume.origin() + Vec3(0, 0, k * volume.spacing().z());
  for (int a = 0; a < 3; ++a) image.SetOrigin(a, origin[a]);
  const double cosines[6] = {1, 0, 0, 0, 1, 0};
  image.SetDirectionCosines(cosines);
  image.SetSlope(volume.encoding().scale);
  image.SetIntercept(volume.encoding().offset);
  const size_t count = size_t(d[0]) * size_t(d[1]);
  const VoxelCode* codes = volume.codes() + size_t(k) * count;
  gdcm::DataElement data(gdcm::Tag(0x7fe0, 0x0010));
  data.SetByteValue(reinterpret_cast<const char*>(codes), uint32_t(count * sizeof(VoxelCode)));
  image.SetDataElement(data);
  gdcm::DataSet& ds = writer.GetFile().GetDataSet();
  gdcm::Attribute<0x0008, 0x0016> sopClass = {"1.2.840.10008.5.1.4.1.1.2"};  // CT Image Storage
  ds.Replace(sopClass.GetAsDataElement());
  gdcm::Attribute<0x0008, 0x0060> modality = {"CT"};
  ds.Replace(modality.GetAsDataElement());
  gdcm::Attribute<0x0020, 0x000d> study = {studyUid.c_str()};
  ds.Replace(study.GetAsDataElement());
  gdcm::Attribute<0x0020, 0x000e> series = {seriesUid.c_str()};
  ds.Replace(series.GetAsDataElement());
  gdcm::Attribute<0x0008, 0x103e> seriesDescription = {description.c_str()};
  ds.Replace(seriesDescription.GetAsDataElement());
  gdcm::Attribute<0x0020, 0x0013> instance = {k + 1};
  ds.Replace(instance.GetAsDataElement());
  writer.SetFileName(file.c_str());
  if (!writer.Write()) throw VolumeWriteError(file, "GDCM could not write the slice");
}

}  // namespace

void writeDicomSeries(const DensityVolume& volume, const fs::path& directory, const std::string& description) {
  std::error_code ec;
  fs::path dir = directory;
  if (dir.filename().empty()) dir = dir.parent_path();  // "ct/" names ct
  if (fs::exists(dir, ec) && !(fs::is_directory(dir, ec) && fs::is_empty(dir, ec)))
    throw VolumeWriteError(dir, "exists and is not an empty directory (a series is written into a new one)");
  const fs::path staging = dir.string() + ".writing";
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  if (ec) throw VolumeWriteError(staging, "cannot create the directory (" + ec.message() + ")");
  gdcm::Trace::SetWarning(false);
  gdcm::UIDGenerator uids;
  const std::string seriesUid = uids.Generate(), studyUid = uids.Generate();
  try {
    for (int32_t k = 0; k < volume.dims()[2]; ++k) {
      char name[32];
      std::snprintf(name, sizeof name, "slice%05d.dcm", k + 1);
      writeSlice(volume, k, staging / name, seriesUid, studyUid, description);
    }
    fs::remove(dir, ec);  // empty, if it exists
    fs::rename(staging, dir, ec);
    if (ec) throw VolumeWriteError(dir, "cannot move the written series into place (" + ec.message() + ")");
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
}

}  // namespace trephine::formats
