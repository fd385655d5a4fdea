#pragma once
// The write check every run folder gets before anything runs (`aggkit run --out`, the points of `aggkit scan`
// and `sweep`, the folders of `aggkit validate`): a folder is usable only if it can be created and a file
// written in it — root may write anywhere by permissions alone, so only writing a file proves it.
#include <filesystem>
#include <string>

namespace aggkit {

// Creates `folder` (and its parents) if needed and writes and removes a probe file in it, named with the
// process id and `tag` (ranks of one job that share the folder give theirs). Otherwise InputError for key
// "--out" naming `out` (the folder the user gave, of which `folder` is part): "a folder that can be created
// and written (why)".
void check_writable_folder(const std::filesystem::path& folder, const std::filesystem::path& out, const std::string& tag = "");

// Whether `name` is such a probe: one a run killed between writing and removing it leaves behind, and which
// is aggkit's own, not the user's.
bool is_write_probe(const std::string& name);

}  // namespace aggkit
