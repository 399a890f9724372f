#pragma once
// Finding the two files of a TetGen mesh: the nodes (.node) and the
// tetrahedra (.ele) share a base name ("brain.node" + "brain.ele.gz"), and
// either may be gzipped. Callers may name either file or the base name.
#include <filesystem>
#include <optional>
#include <string>

namespace trephine::formats {

enum class TetGenPart { kNode, kEle };

// The other file of the pair: for a node file the first existing of
// <base>.ele and <base>.ele.gz, for an element file <base>.node and
// <base>.node.gz. <base> is `file` without ".gz" and without ".node"/".ele"
// (or whatever single extension it has). Throws TetMeshReadError naming the
// names tried when neither exists.
std::filesystem::path findTetGenPartner(const std::filesystem::path& file, TetGenPart fileIs);

// <base>.node or <base>.node.gz when `base` names a TetGen pair without extension.
std::optional<std::filesystem::path> findTetGenNodeForBase(const std::filesystem::path& base);

}  // namespace trephine::formats
