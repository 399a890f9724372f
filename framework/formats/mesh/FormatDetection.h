#pragma once
// Recognising a mesh format from the first bytes of a file's content (after
// gunzipping), never from its name: data sets ship VTK XML files named .vtk
// and TetGen files named .txt.
#include <string_view>

namespace trephine::formats {

enum class MeshFormat {
  kUnknown,
  kTetGen,       // a count first ("30871 3 0 0" or "145391 4 1"), after '#' comments
  kMedit,        // MeshVersionFormatted first, after '#' comments
  kMeditBinary,  // .meshb: the 32-bit integer 1 first (refused)
  kGmsh,         // a $Section line first ($MeshFormat, $NOD, $Comments, ...)
  kVtkLegacy,    // "# vtk DataFile Version"
  kVtu,          // XML ('<' first): VTK XML
};

MeshFormat detectMeshFormat(std::string_view content);

}  // namespace trephine::formats
