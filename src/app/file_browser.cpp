#include "app/file_browser.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace sculpt::app {
namespace fs = std::filesystem;

namespace {

std::string lower(std::string text) {
    for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

bool lessByName(const FolderEntry& a, const FolderEntry& b) {
    const std::string la = lower(a.name), lb = lower(b.name);
    return la != lb ? la < lb : a.name < b.name;
}

std::string homeFolder() {
    const char* home = std::getenv("HOME");
    return home && *home ? home : "/";
}

}  // namespace

bool hasExtension(const std::string& name, const std::vector<std::string>& extensions) {
    if (extensions.empty()) return true;
    const std::string lowered = lower(name);
    for (const std::string& extension : extensions) {
        const std::string e = lower(extension);
        if (lowered.size() > e.size() && lowered.compare(lowered.size() - e.size(), e.size(), e) == 0) return true;
    }
    return false;
}

FolderListing listFolder(const std::string& folder, const std::vector<std::string>& extensions, bool showHidden) {
    FolderListing listing;
    std::error_code error;
    fs::path absolute = fs::absolute(folder.empty() ? "." : folder, error);
    if (error) absolute = folder;
    listing.folder = absolute.lexically_normal().string();
    if (listing.folder.size() > 1 && listing.folder.back() == '/') listing.folder.pop_back();
    try {
        fs::directory_iterator it(listing.folder, fs::directory_options::skip_permission_denied, error);
        if (error) {
            listing.error = "Cannot read " + listing.folder + ": " + error.message();
            return listing;
        }
        for (; it != fs::directory_iterator(); it.increment(error)) {
            if (error) break;
            const std::string name = it->path().filename().string();
            if (name.empty() || (!showHidden && name[0] == '.')) continue;
            std::error_code entryError;
            const bool isFolder = it->is_directory(entryError);  // follows links: a link to a folder is a folder
            if (entryError) continue;
            if (isFolder) {
                listing.entries.push_back({name, true, 0});
            } else if (it->is_regular_file(entryError) && !entryError && hasExtension(name, extensions)) {
                const std::uintmax_t bytes = it->file_size(entryError);
                listing.entries.push_back({name, false, entryError ? 0 : bytes});
            }
        }
        if (error) {
            listing.entries.clear();
            listing.error = "Cannot read " + listing.folder + ": " + error.message();
            return listing;
        }
    } catch (const std::exception& e) {  // bad_alloc or a filesystem_error the error_code overloads missed
        listing.entries.clear();
        listing.error = "Cannot read " + listing.folder + ": " + e.what();
        return listing;
    }
    std::stable_partition(listing.entries.begin(), listing.entries.end(), [](const FolderEntry& e) { return e.isFolder; });
    const auto firstFile = std::find_if(listing.entries.begin(), listing.entries.end(),
                                        [](const FolderEntry& e) { return !e.isFolder; });
    std::sort(listing.entries.begin(), firstFile, lessByName);
    std::sort(firstFile, listing.entries.end(), lessByName);
    return listing;
}

std::string joinPath(const std::string& folder, const std::string& typed) {
    if (typed.empty()) return fs::path(folder).lexically_normal().string();
    fs::path path;
    if (typed == "~") path = homeFolder();
    else if (typed.rfind("~/", 0) == 0) path = fs::path(homeFolder()) / typed.substr(2);
    else if (fs::path(typed).is_absolute()) path = typed;
    else path = fs::path(folder) / typed;
    std::string normal = path.lexically_normal().string();
    if (normal.size() > 1 && normal.back() == '/') normal.pop_back();
    return normal;
}

std::string parentFolder(const std::string& folder) {
    std::string normal = fs::path(folder).lexically_normal().string();
    while (normal.size() > 1 && normal.back() == '/') normal.pop_back();
    const fs::path path(normal);
    if (path == path.root_path()) return normal;  // the root stays the root
    const fs::path parent = path.parent_path();
    return parent.empty() ? std::string(".") : parent.string();
}

std::string folderOfPath(const std::string& path) {
    const fs::path parent = fs::path(path).parent_path();
    return parent.empty() ? std::string(".") : parent.string();
}

std::string fileNameOfPath(const std::string& path) { return fs::path(path).filename().string(); }

std::string withDefaultExtension(const std::string& path, const std::string& extension,
                                 const std::vector<std::string>& extensions) {
    if (path.empty() || path.back() == '/' || hasExtension(path, extensions)) return path;
    return path + extension;
}

OpenCheck checkOpenPath(const std::string& path) {
    OpenCheck check;
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (error || !fs::exists(status)) {
        check.error = fileNameOfPath(path) + ": no such file";
        return check;
    }
    if (fs::is_directory(status)) {
        check.isFolder = true;
        return check;
    }
    if (!fs::is_regular_file(status)) {
        check.error = fileNameOfPath(path) + ": not a regular file";
        return check;
    }
    check.ok = true;
    return check;
}

SaveCheck checkSavePath(const std::string& path) {
    SaveCheck check;
    const std::string name = fileNameOfPath(path);
    if (path.empty() || name.empty() || name == "." || name == "..") {
        check.error = "Type a file name.";
        return check;
    }
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (!error && fs::is_directory(status)) {
        check.verdict = SaveVerdict::EnterFolder;
        return check;
    }
    if (!error && fs::exists(status)) {
        if (!fs::is_regular_file(status)) {
            check.error = name + " exists and is not a regular file.";
            return check;
        }
        check.verdict = SaveVerdict::ConfirmReplace;
        return check;
    }
    const std::string folder = folderOfPath(path);
    std::error_code folderError;
    if (!fs::is_directory(folder, folderError)) {
        check.error = "The folder " + folder + " does not exist.";
        return check;
    }
    check.verdict = SaveVerdict::Write;
    return check;
}

}  // namespace sculpt::app
