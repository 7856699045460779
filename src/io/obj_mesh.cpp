// OBJ loading: validating pre-pass (obj_scan.cpp), then tinyobjloader, then a face-by-face agreement
// check between the two before anything reaches the caller.
#include "io/obj_mesh.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <istream>
#include <map>
#include <new>
#include <set>
#include <sstream>
#include <streambuf>
#include <system_error>
#include <unordered_map>
#include <utility>

#include <tiny_obj_loader.h>

#include "io/atomic_file.h"
#include "io/huge_pages.h"
#include "io/obj_scan.h"
#include "io/polygon_triangulation.h"

namespace sculpt::io {

namespace {

constexpr off_t kMaxMaterialFileBytes = 16 << 20;  // a .mtl is a few kB; anything huge is not one
constexpr size_t kMaxWarnings = 32;                // a broken file must not flood the log

// Where the scan ends in a load's ObjLoadProgress (measured on a 1M-vertex file: the scan is about 80% of the
// load after reading the file; triangulation most of the rest).
constexpr float kScanEnd = 0.8f;

void reportProgress(ObjLoadProgress* progress, float fraction) {
    if (progress) progress->fraction.store(fraction, std::memory_order_relaxed);
}
bool cancelRequested(const ObjLoadProgress* progress) {
    return progress && progress->cancel.load(std::memory_order_relaxed);
}


bool isPlainFileName(const std::string& name) {
    if (name.empty() || name == "." || name == "..") return false;
    for (char c : name)
        if (c == '/' || c == '\\' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return false;
    return true;
}

// Reads a whole regular file of at most maxBytes. Opens first and checks the opened descriptor, so a
// file swapped for a FIFO or device between the check and the open is still refused; O_NONBLOCK keeps
// a FIFO from blocking the open.
bool readRegularFile(const std::string& path, off_t maxBytes, std::string& contents, std::string& why) {
    struct stat info {};
    if (::stat(path.c_str(), &info) != 0) {
        why = errnoText(errno);
        return false;
    }
    if (!S_ISREG(info.st_mode)) {
        why = S_ISDIR(info.st_mode) ? "it is a folder" : "not a regular file";
        return false;
    }
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        why = errnoText(errno);
        return false;
    }
    bool ok = ::fstat(fd, &info) == 0 && S_ISREG(info.st_mode);
    if (!ok) why = "not a regular file";
    if (ok && maxBytes > 0 && info.st_size > maxBytes) {
        why = "larger than " + std::to_string(maxBytes >> 20) + " MiB";
        ok = false;
    }
    if (ok) {
        contents.clear();
        reserveWithHugePages(contents, static_cast<size_t>(info.st_size));  // a 200 MB OBJ: 100 faults, not 50,000
        contents.resize(static_cast<size_t>(info.st_size));
        size_t done = 0;
        while (done < contents.size()) {
            const ssize_t got = ::read(fd, &contents[done], contents.size() - done);
            if (got < 0 && errno == EINTR) continue;
            if (got < 0) {
                why = errnoText(errno);
                ok = false;
                break;
            }
            if (got == 0) break;  // the file shrank meanwhile
            done += static_cast<size_t>(got);
        }
        contents.resize(done);
    }
    ::close(fd);
    return ok;
}

// Loads `mtllib` files for tinyobjloader, but only a plain file name that is a regular file of sane
// size in the OBJ's own folder: an OBJ from the internet must not make us read ../../etc/passwd,
// /dev/zero or a FIFO. Anything refused or missing is a warning and the materials are skipped.
class ConfinedMaterialReader : public tinyobj::MaterialReader {
public:
    ConfinedMaterialReader(std::string folder, std::string displayName, std::vector<std::string>& warnings)
        : folder_(std::move(folder)), name_(std::move(displayName)), warnings_(warnings) {}

    bool operator()(const std::string& matId, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* matMap, std::string* warn, std::string* err) override {
        const std::string shown = "mtllib '" + normalizeForMessage(matId) + "'";
        if (folder_.empty()) return refuse(shown + ": no folder to look in; materials skipped");
        if (!isPlainFileName(matId))
            return refuse(shown + " refused: only a plain file name in the OBJ's folder is read; materials skipped");
        std::string contents, why;
        if (!readRegularFile(folder_ + "/" + matId, kMaxMaterialFileBytes, contents, why))
            return refuse(shown + " not loaded (" + why + "); materials skipped");
        for (char c : contents) {
            const unsigned char u = static_cast<unsigned char>(c);
            if ((u < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') || u == 0x7f)
                return refuse(shown + " is not a text file; materials skipped");
        }
        std::istringstream stream(contents);
        tinyobj::LoadMtl(matMap, materials, &stream, warn, err);
        return true;
    }

private:
    static std::string normalizeForMessage(const std::string& s) {
        std::string out;
        for (size_t i = 0; i < s.size() && i < 80; ++i) {
            const unsigned char c = static_cast<unsigned char>(s[i]);
            out += (c < 0x20 || c == 0x7f) ? '?' : s[i];
        }
        return out;
    }
    bool refuse(const std::string& message) {
        warnings_.push_back(name_ + ": " + message);
        return false;
    }

    std::string folder_;
    std::string name_;
    std::vector<std::string>& warnings_;
};

std::string folderOf(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}

// Adds tinyobjloader's warnings (one per line in warn) to ours, skipping its generic notes that
// ours already say better.
void addTinyobjWarnings(const std::string& warn, const std::string& displayName, std::vector<std::string>& warnings) {
    size_t begin = 0;
    while (begin < warn.size()) {
        size_t end = warn.find('\n', begin);
        if (end == std::string::npos) end = warn.size();
        const std::string line = warn.substr(begin, end - begin);
        begin = end + 1;
        // Skipped: notes our own warnings already give ("Failed to load material file(s)"), and the
        // unnamed-group note for "g " which serializeObj writes on purpose.
        if (line.empty() || line == "." || line.rfind("Failed to load material file(s)", 0) == 0 ||
            line.rfind("Empty group name", 0) == 0)
            continue;
        warnings.push_back(displayName + ": " + line);
    }
}

void deliverWarnings(std::vector<std::string>& collected, std::vector<std::string>* warnings) {
    if (!warnings) return;
    std::set<std::string> seen;
    size_t dropped = 0;
    for (std::string& w : collected) {
        if (!seen.insert(w).second) continue;
        if (seen.size() > kMaxWarnings) {
            ++dropped;
            continue;
        }
        warnings->push_back(std::move(w));
    }
    if (dropped > 0) warnings->push_back("... and " + std::to_string(dropped) + " more warning(s)");
}

// tinyobjloader's result must describe exactly the faces the pre-pass validated; anything else
// means the two disagree on the file and no geometry is trusted.
Status checkAgreement(const ObjScan& scan, const tinyobj::attrib_t& attrib, const std::vector<tinyobj::shape_t>& shapes,
                      const std::string& displayName) {
    auto disagree = [&](size_t line, const std::string& what) {
        std::string where = displayName;
        if (line > 0) where += ":" + std::to_string(line);
        return Status::error(where + ": internal error: tinyobjloader and the validating reader disagree (" + what +
                             "); please report this file");
    };
    if (attrib.vertices.size() != scan.positions.size()) return disagree(0, "vertex count");
    if (attrib.texcoords.size() / 2 != scan.texcoords.size() / 3) return disagree(0, "texture coordinate count");
    if (attrib.normals.size() / 3 != static_cast<size_t>(scan.normalCount)) return disagree(0, "normal count");

    const size_t faceCount = scan.faceLine.size();
    std::unordered_map<std::string, int> groupIndex;
    for (size_t g = 0; g < scan.groupNames.size(); ++g) groupIndex.emplace(scan.groupNames[g], static_cast<int>(g));
    size_t f = 0;
    size_t notForTinyobj = 0;  // into scan.facesNotForTinyobj (ascending): faces tinyobjloader never saw
    const auto skipFacesNotForTinyobj = [&] {
        while (notForTinyobj < scan.facesNotForTinyobj.size() &&
               static_cast<size_t>(scan.facesNotForTinyobj[notForTinyobj]) == f) {
            ++notForTinyobj;
            ++f;
        }
    };
    for (const tinyobj::shape_t& shape : shapes) {
        const auto found = groupIndex.find(normalizeObjName(shape.name));
        const int group = found == groupIndex.end() ? -1 : found->second;
        size_t corner = 0;
        for (unsigned char cornersInFace : shape.mesh.num_face_vertices) {
            skipFacesNotForTinyobj();
            if (f >= faceCount) return disagree(0, "face count");
            const size_t line = static_cast<size_t>(scan.faceLine[f]);
            const size_t start = static_cast<size_t>(scan.faceStart[f]);
            if (static_cast<size_t>(scan.faceStart[f + 1]) - start != cornersInFace)
                return disagree(line, "corner count");
            if (corner + cornersInFace > shape.mesh.indices.size()) return disagree(line, "corner count");
            for (size_t k = 0; k < cornersInFace; ++k) {
                const tinyobj::index_t& index = shape.mesh.indices[corner + k];
                if (index.vertex_index != scan.cornerVertex[start + k] ||
                    index.texcoord_index != scan.cornerTexcoord[start + k] ||
                    index.normal_index != scan.cornerNormal[start + k])
                    return disagree(line, "corner indices");
            }
            if (group != scan.faceGroup[f]) return disagree(line, "group name");
            corner += cornersInFace;
            ++f;
        }
    }
    skipFacesNotForTinyobj();
    if (f != faceCount) return disagree(0, "face count");
    return Status::success();
}

// tinyobjloader's SplitString(s, ' ', '\\'): the file names of a `mtllib` line (a backslash escapes a blank).
std::vector<std::string> splitLibraryNames(const std::string& s) {
    std::vector<std::string> names;
    std::string token;
    bool escaping = false;
    for (char c : s) {
        if (escaping) {
            escaping = false;
        } else if (c == '\\') {
            escaping = true;
            continue;
        } else if (c == ' ') {
            if (!token.empty()) names.push_back(token);
            token.clear();
            continue;
        }
        token += c;
    }
    names.push_back(token);
    return names;
}

// The .mtl files an OBJ names, read as tinyobjloader's LoadObj reads them (its `mtllib` and `usemtl` handling,
// replayed in file order) through ConfinedMaterialReader and tinyobj::LoadMtl. Only what they report is kept:
// materials are kept by name (usemtl), their definitions are not used.
void readMaterialLibraries(const ObjScan& scan, const std::string& baseDir, const std::string& displayName,
                           std::vector<std::string>& collected) {
    if (scan.materialStatements.empty()) return;
    ConfinedMaterialReader reader(baseDir, displayName, collected);
    std::vector<tinyobj::material_t> materials;
    std::map<std::string, int> materialMap;
    std::set<std::string> loaded;
    std::string warn, err;
    for (const ObjScan::MaterialStatement& statement : scan.materialStatements) {
        if (!statement.library) {
            if (materialMap.count(statement.text) == 0) warn += "material [ '" + statement.text + "' ] not found in .mtl\n";
            continue;
        }
        bool found = false;
        for (const std::string& file : splitLibraryNames(statement.text)) {
            if (loaded.count(file) > 0) {
                found = true;
                continue;
            }
            std::string fileWarn, fileErr;
            const bool ok = reader(file, &materials, &materialMap, &fileWarn, &fileErr);
            warn += fileWarn;
            err += fileErr;
            if (ok) {
                found = true;
                loaded.insert(file);
                break;
            }
        }
        if (!found) warn += "Failed to load material file(s). Use default material.\n";
    }
    addTinyobjWarnings(warn, displayName, collected);
    if (!err.empty()) addTinyobjWarnings(err, displayName, collected);  // .mtl problems only; not fatal
}

// text is kept as the mesh's source (moved in on success).
Status loadChecked(std::string& text, const std::string& displayName, const std::string& baseDir, ObjMesh& out,
                   std::vector<std::string>& collected, ObjLoadProgress* progress) {
    const Status cancelled = Status::error(displayName + ": loading cancelled");
    ObjScan scan;
    Status status = scanObjText(text, displayName, scan, progress, kScanEnd);
    collected.insert(collected.end(), scan.warnings.begin(), scan.warnings.end());
    if (!status) return status;
    reportProgress(progress, kScanEnd);
    if (cancelRequested(progress)) return cancelled;

    // The text is parsed once, by the validating reader (obj_scan.h), which keeps the exact digits
    // tinyobjloader's number parser loses. tinyobjloader reads the .mtl files, in the order and with the
    // messages its LoadObj has; the tests and the fuzzer check that it reads the faces the same
    // (crossCheckObjWithTinyobj).
    readMaterialLibraries(scan, baseDir, displayName, collected);
    if (cancelRequested(progress)) return cancelled;

    // note: tinyobjloader's tryParseDouble is not correctly rounded (a written-then-read file would drift
    // in the last bits) and it keeps only u v of a `vt` line: positions and texture coordinates are the
    // reader's. The arrays are moved, not copied.
    ObjMesh mesh;
    const Eigen::Index vertexCount = static_cast<Eigen::Index>(scan.positions.size() / 3);
    mesh.positions = Eigen::Map<const Positions>(scan.positions.data(), vertexCount, 3);
    scan.positions = std::vector<double>();
    const Eigen::Index texcoordCount = static_cast<Eigen::Index>(scan.texcoords.size() / 3);
    mesh.texcoords = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(scan.texcoords.data(),
                                                                                                 texcoordCount, 3)
                         .leftCols(scan.texcoordComponents);

    mesh.faceStart = std::move(scan.faceStart);
    mesh.cornerVertex = std::move(scan.cornerVertex);
    mesh.cornerTexcoord = std::move(scan.cornerTexcoord);
    mesh.cornerNormal = std::move(scan.cornerNormal);
    mesh.faceGroup = std::move(scan.faceGroup);
    mesh.groupNames = std::move(scan.groupNames);
    mesh.faceMaterial = std::move(scan.faceMaterial);
    mesh.materialNames = std::move(scan.materialNames);
    mesh.materialLibraries = std::move(scan.materialLibraries);

    const ObjTriangulationReport triangulation = triangulateObjFaces(mesh);
    if (triangulation.fannedFaces > 0)
        collected.push_back(displayName + ": " + std::to_string(triangulation.fannedFaces) +
                            " face(s) could not be triangulated exactly and are drawn as a fan of their corners "
                            "(first on line " + std::to_string(scan.faceLine[static_cast<size_t>(triangulation.firstFannedFace)]) +
                            ": " + triangulation.firstReason + ")");
    if (cancelRequested(progress)) return cancelled;

    auto source = std::make_shared<ObjSource>();
    source->positionSpans = std::move(scan.positionSpans);
    source->normalSpans = std::move(scan.normalSpans);
    source->text = std::move(text);
    mesh.source = std::move(source);
    out = std::move(mesh);
    reportProgress(progress, 1.0f);
    return Status::success();
}

}  // namespace

ObjTriangulationReport triangulateObjFaces(ObjMesh& mesh) {
    ObjTriangulationReport report;
    const int faceCount = mesh.faceCount();
    // note: a face of N corners gives at most N - 2 triangles, so this is the final size unless corners coincide.
    const Eigen::Index maxTriangles = static_cast<Eigen::Index>(mesh.cornerVertex.size()) - 2 * faceCount;
    Triangles triangles(maxTriangles, 3);
    adviseHugePages(triangles.data(), static_cast<size_t>(triangles.size()) * sizeof(int));
    std::vector<int> triangleFace;
    reserveWithHugePages(triangleFace, static_cast<size_t>(maxTriangles));
    triangleFace.resize(static_cast<size_t>(maxTriangles));
    Eigen::Index t = 0;
    std::vector<double> corners;  // scratch, reused: N x 3 row-major
    std::vector<CornerTriangle> polygon;
    for (int f = 0; f < faceCount; ++f) {
        const int first = mesh.faceStart[f];
        const int n = mesh.faceStart[f + 1] - first;
        const int* vertex = &mesh.cornerVertex[static_cast<size_t>(first)];
        if (n == 3) {
            triangles.row(t) << vertex[0], vertex[1], vertex[2];
            triangleFace[static_cast<size_t>(t++)] = f;
            continue;
        }
        corners.resize(3 * static_cast<size_t>(n));
        for (int c = 0; c < n; ++c)
            for (int k = 0; k < 3; ++k) corners[3 * static_cast<size_t>(c) + k] = mesh.positions(vertex[c], k);
        Status status = triangulatePolygon(Eigen::Map<const Positions>(corners.data(), n, 3), polygon);
        if (status && polygon.size() > static_cast<size_t>(n - 2))
            status = Status::error("internal error: more triangles than a polygon can have");  // never expected
        if (!status) {
            if (report.fannedFaces++ == 0) {
                report.firstFannedFace = f;
                report.firstReason = status.message;
            }
            polygon.clear();
            for (int c = 1; c + 1 < n; ++c) polygon.push_back({0, c, c + 1});
        }
        for (const CornerTriangle& corner : polygon) {
            triangles.row(t) << vertex[corner[0]], vertex[corner[1]], vertex[corner[2]];
            triangleFace[static_cast<size_t>(t++)] = f;
        }
    }
    triangles.conservativeResize(t, 3);
    triangleFace.resize(static_cast<size_t>(t));
    mesh.triangles = std::move(triangles);
    mesh.triangleFace = std::move(triangleFace);
    return report;
}

namespace {

Status loadOwnedText(std::string& text, const std::string& displayName, const std::string& baseDir, ObjMesh& out,
                     std::vector<std::string>* warnings, ObjLoadProgress* progress) {
    std::vector<std::string> collected;
    Status status;
    // No exception may cross the io boundary: out of memory on a huge file is an ordinary error.
    try {
        status = loadChecked(text, displayName, baseDir, out, collected, progress);
    } catch (const std::bad_alloc&) {
        status = Status::error(displayName + ": not enough memory to load the file");
    } catch (const std::exception& e) {
        status = Status::error(displayName + ": unexpected error while loading: " + e.what());
    } catch (...) {
        status = Status::error(displayName + ": unexpected error while loading");
    }
    try {
        deliverWarnings(collected, warnings);
    } catch (...) {
        // Losing warnings under memory pressure is acceptable; losing the status is not.
    }
    return status;
}

}  // namespace

Status loadObjFromText(const std::string& text, const std::string& displayName, const std::string& baseDir,
                       ObjMesh& out, std::vector<std::string>* warnings, ObjLoadProgress* progress) {
    std::string copy;
    try {
        copy = text;  // becomes the mesh's source
    } catch (const std::bad_alloc&) {
        return Status::error(displayName + ": not enough memory to load the file");
    }
    return loadOwnedText(copy, displayName, baseDir, out, warnings, progress);
}

Status crossCheckObjWithTinyobj(const std::string& text, const std::string& displayName) {
    try {
        ObjScan scan;
        if (!scanObjText(text, displayName, scan, nullptr, 1.0f, /*tinyobjCopy=*/true))
            return Status::success();  // refused before any parse
        const std::string& tinyobjText = scan.sanitizedText.empty() ? text : scan.sanitizedText;
        std::istringstream stream(tinyobjText);
        tinyobj::attrib_t attrib;
        std::vector<tinyobj::shape_t> shapes;
        std::vector<tinyobj::material_t> materials;
        std::string warn, err;
        // No material reader: `mtllib` opens nothing here.
        if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, nullptr, /*triangulate=*/false,
                              /*default_vcols_fallback=*/false))
            return Status::error(displayName + ": tinyobjloader rejected the file: " + err);
        return checkAgreement(scan, attrib, shapes, displayName);
    } catch (const std::bad_alloc&) {
        return Status::error(displayName + ": not enough memory to cross-check the file");
    }
}

Status loadObj(const std::string& path, ObjMesh& out, std::vector<std::string>* warnings, ObjLoadProgress* progress) {
    try {
        std::string text, why;
        if (!readRegularFile(path, 0, text, why)) return Status::error("cannot read '" + path + "': " + why);
        if (cancelRequested(progress)) return Status::error(path + ": loading cancelled");
        return loadOwnedText(text, path, folderOf(path), out, warnings, progress);
    } catch (const std::bad_alloc&) {
        return Status::error(path + ": not enough memory to load the file");
    } catch (...) {
        return Status::error(path + ": unexpected error while loading");
    }
}

}  // namespace sculpt::io
