// The logic of the window's file dialog, without any UI: folder listings filtered by extension, path joining,
// and the checks before opening or saving (a folder, a missing folder, a file that would be replaced). Plain
// functions over std::filesystem, so tests exercise them without Dear ImGui; the dialog (file_dialog.cpp)
// only draws their results.
//
// No function here throws: every file-system failure (permission denied, a folder that vanished) becomes a
// message.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace sculpt::app {

struct FolderEntry {
    std::string name;          // file or folder name, no path
    bool isFolder = false;
    std::uintmax_t bytes = 0;  // files only
};

struct FolderListing {
    std::string folder;                // absolute, normalised
    std::vector<FolderEntry> entries;  // folders first, then files; each group sorted by name, case-insensitively
    std::string error;                 // non-empty: the folder could not be read (entries then empty)
};

// Lists `folder`: its sub-folders and the files whose name ends in one of `extensions` (".obj"; compared
// case-insensitively; empty list = every file). Names starting with '.' are left out unless showHidden.
// Entries that cannot be examined (a dangling link, a file removed meanwhile) are skipped.
FolderListing listFolder(const std::string& folder, const std::vector<std::string>& extensions,
                         bool showHidden = false);

// Whether name ends in one of the extensions, case-insensitively (".OBJ" matches ".obj"); true for an empty list.
bool hasExtension(const std::string& name, const std::vector<std::string>& extensions);

// What the user typed, taken relative to `folder` unless absolute; "~" or "~/..." is the home folder.
// Normalised lexically ("a/./b/../c" -> "a/c"); symbolic links are not resolved.
std::string joinPath(const std::string& folder, const std::string& typed);

// The folder above `folder` (the root stays the root).
std::string parentFolder(const std::string& folder);

// The folder part and file-name part of a path ("/a/b.obj" -> "/a", "b.obj").
std::string folderOfPath(const std::string& path);
std::string fileNameOfPath(const std::string& path);

// path with `extension` appended when it has none of `extensions` ("mesh" -> "mesh.obj"); unchanged otherwise.
std::string withDefaultExtension(const std::string& path, const std::string& extension,
                                 const std::vector<std::string>& extensions);

// What may happen to a path chosen in an Open dialog.
struct OpenCheck {
    bool ok = false;
    bool isFolder = false;  // the path is a folder: the dialog enters it instead
    std::string error;      // why it cannot be opened ("no such file", "not a regular file")
};
OpenCheck checkOpenPath(const std::string& path);

// What may happen to a path chosen in a Save dialog.
enum class SaveVerdict {
    Write,           // a new file in an existing folder
    ConfirmReplace,  // a file is there: ask "Replace?" before writing
    EnterFolder,     // the path is a folder: the dialog enters it instead
    Refuse,          // cannot be written there (missing folder, no file name, not a regular file)
};
struct SaveCheck {
    SaveVerdict verdict = SaveVerdict::Refuse;
    std::string error;  // with Refuse
};
SaveCheck checkSavePath(const std::string& path);

}  // namespace sculpt::app
