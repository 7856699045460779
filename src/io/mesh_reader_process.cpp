// Reading a PLY, STL, glTF or OFF file in a child process (importInReaderProcess) and the payload it sends back.
#include "io/mesh_file_internal.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <deque>
#include <functional>

#include "io/huge_pages.h"
#include "io/isolated_call.h"

namespace sculpt::io {

namespace {

// A glTF file is binary (GLB: "glTF", a version and its length) or a JSON object, whatever its extension says.
Status checkGltf(const std::string& bytes, const std::string& name, bool binary) {
    if (binary) {
        uint32_t length = 0;
        if (bytes.size() >= 12) std::memcpy(&length, bytes.data() + 8, 4);
        if (bytes.size() < 12 || length > bytes.size())
            return Status::error(name + ": the file ends early: its GLB header declares " + std::to_string(length) +
                                 " bytes, the file has " + std::to_string(bytes.size()) + " (truncated?)");
        return Status::success();
    }
    const size_t start = detail::firstNonBlank(bytes);
    if (start >= bytes.size() || bytes[start] != '{')
        return Status::error(name + ": not a glTF file (neither a binary GLB, which starts with \"glTF\", nor JSON)");
    return Status::success();
}

// How PayloadWriter::indices sent an array.
constexpr uint8_t kElementwise = 0, kOneValue = 1, kSameAsOther = 2;

// What the reader process sends back: its verdict, its notes and the mesh without triangles. Plain bytes in
// this program's own layout (both ends run the same binary). The writer and the reader share one list of the
// fields (payloadFields), so the two directions cannot drift apart.
// PayloadWriter builds the payload as pieces for IsolatedChannel::result: the small fields copied here, each
// large array referenced where it lies (the caller copies it out of the reader's memory once, with no copy
// here). The arrays referenced must outlive the result() call.
class PayloadWriter {
public:
    template <typename T>
    bool pod(const T& value) {
        raw(&value, sizeof value);
        return true;
    }
    template <typename T>
    bool array(const std::vector<T>& v) {
        pod(static_cast<uint64_t>(v.size()));
        bytes(v.data(), v.size() * sizeof(T));
        return true;
    }
    // An index array that is often one value throughout (PLY's corner normals, a single group) or a copy of
    // another (per-vertex texture coordinates: cornerTexcoord = cornerVertex): sent as that, not element by element.
    bool indices(const std::vector<int>& v, const std::vector<int>& likely) {
        if (v == likely) return pod(kSameAsOther) && pod(static_cast<uint64_t>(v.size()));
        if (!v.empty() && std::all_of(v.begin(), v.end(), [&](int i) { return i == v[0]; }))
            return pod(kOneValue) && pod(static_cast<uint64_t>(v.size())) && pod(v[0]);
        return pod(kElementwise) && array(v);
    }
    bool text(const std::string& s) {
        pod(static_cast<uint64_t>(s.size()));
        raw(s.data(), s.size());
        return true;
    }
    bool texts(const std::vector<std::string>& list) {
        pod(static_cast<uint64_t>(list.size()));
        for (const std::string& s : list) text(s);
        return true;
    }
    template <typename Matrix>
    bool matrix(const Matrix& m) {
        pod(static_cast<int64_t>(m.rows()));
        pod(static_cast<int64_t>(m.cols()));
        pod(static_cast<uint64_t>(m.size()));
        bytes(m.data(), static_cast<size_t>(m.size()) * sizeof(typename Matrix::Scalar));
        return true;
    }
    const std::vector<IsolatedPiece>& pieces() {
        seal();
        return pieces_;
    }

private:
    void raw(const void* data, size_t size) {
        if (!open_) small_.emplace_back();
        open_ = true;
        small_.back().append(static_cast<const char*>(data), size);
    }
    void bytes(const void* data, size_t size) {
        if (size < 65536) return raw(data, size);
        seal();
        pieces_.push_back({data, size});
    }
    void seal() {
        if (open_) pieces_.push_back({small_.back().data(), small_.back().size()});
        open_ = false;
    }
    std::deque<std::string> small_;  // a deque: a sealed string is never moved by the ones added after it
    std::vector<IsolatedPiece> pieces_;
    bool open_ = false;
};

class PayloadReader {
public:
    explicit PayloadReader(const std::string& bytes) : bytes_(bytes) {}
    template <typename T>
    bool pod(T& value) {
        if (bytes_.size() - at_ < sizeof value) return false;
        std::memcpy(&value, bytes_.data() + at_, sizeof value);
        at_ += sizeof value;
        return true;
    }
    template <typename T>
    bool array(std::vector<T>& out) {
        uint64_t count = 0;
        if (!pod(count) || count > (bytes_.size() - at_) / sizeof(T)) return false;
        reserveWithHugePages(out, count);
        out.resize(count);
        if (count > 0) std::memcpy(out.data(), bytes_.data() + at_, count * sizeof(T));
        at_ += count * sizeof(T);
        return true;
    }
    bool indices(std::vector<int>& v, const std::vector<int>& likely) {
        uint8_t how = 0;
        uint64_t count = 0;
        int value = 0;
        if (!pod(how)) return false;
        if (how == kElementwise) return array(v);
        if (how == kSameAsOther) {
            if (!pod(count) || count != likely.size()) return false;
            reserveWithHugePages(v, count);
            v.assign(likely.begin(), likely.end());
            return true;
        }
        // A count no bigger than the payload, as for arrays: a damaged payload never asks for unbounded memory.
        if (how != kOneValue || !pod(count) || count > bytes_.size() || !pod(value)) return false;
        reserveWithHugePages(v, count);
        v.assign(count, value);
        return true;
    }
    bool text(std::string& s) {
        std::vector<char> chars;
        if (!array(chars)) return false;
        s.assign(chars.begin(), chars.end());
        return true;
    }
    bool texts(std::vector<std::string>& list) {
        uint64_t count = 0;
        if (!pod(count) || count > bytes_.size() - at_) return false;
        list.resize(count);
        for (std::string& s : list)
            if (!text(s)) return false;
        return true;
    }
    template <typename Matrix>
    bool matrix(Matrix& m) {
        using Scalar = typename Matrix::Scalar;
        int64_t rows = 0, cols = 0;
        uint64_t count = 0;
        if (!pod(rows) || !pod(cols) || !pod(count) || rows < 0 || cols < 0 ||
            static_cast<uint64_t>(rows) * static_cast<uint64_t>(cols) != count || count > (bytes_.size() - at_) / sizeof(Scalar))
            return false;
        constexpr int64_t fixedCols = Matrix::ColsAtCompileTime;  // Eigen::Dynamic (-1) when not fixed
        if (fixedCols != Eigen::Dynamic && cols != fixedCols && rows > 0) return false;
        m.resize(rows, fixedCols != Eigen::Dynamic ? fixedCols : cols);
        adviseHugePages(m.data(), count * sizeof(Scalar));
        if (count > 0) std::memcpy(m.data(), bytes_.data() + at_, count * sizeof(Scalar));
        at_ += count * sizeof(Scalar);
        return true;
    }
    bool done() const { return at_ == bytes_.size(); }

private:
    const std::string& bytes_;
    size_t at_ = 0;
};

// The "likely" array of an index array that is expected to be one value throughout, or given element by element.
// (Each likely array comes earlier in payloadFields than the array it may equal: the reader has it by then.)
const std::vector<int> kNoIndices;

// The payload after the verdict and notes, in order (Mesh: ObjMesh to read into, const ObjMesh to write).
template <typename Channel, typename Mesh>
bool payloadFields(Channel& c, Mesh& mesh) {
    return c.matrix(mesh.positions) && c.array(mesh.faceStart) && c.array(mesh.cornerVertex) &&
           c.indices(mesh.cornerTexcoord, mesh.cornerVertex) && c.indices(mesh.cornerNormal, mesh.cornerTexcoord) &&
           c.matrix(mesh.texcoords) && c.indices(mesh.faceGroup, kNoIndices) && c.texts(mesh.groupNames) &&
           c.indices(mesh.faceMaterial, kNoIndices) &&
           c.texts(mesh.materialNames) && c.matrix(mesh.vertexColors) && c.matrix(mesh.vertexNormals);
}

// The whole payload into w (whose pieces reference mesh's arrays).
void encodePayload(const Status& status, const std::vector<std::string>& notes, const ObjMesh& mesh, PayloadWriter& w) {
    w.pod(static_cast<uint8_t>(status.ok));
    w.text(status.message);
    w.texts(notes);
    payloadFields(w, mesh);
}

bool decodePayload(const std::string& bytes, Status& status, std::vector<std::string>& notes, ObjMesh& mesh) {
    PayloadReader r(bytes);
    uint8_t ok = 0;
    const bool read = r.pod(ok) && r.text(status.message) && r.texts(notes) && payloadFields(r, mesh) && r.done();
    status.ok = ok != 0;
    return read;
}

Status finishImport(const Status& status, const std::vector<std::string>& readerNotes, ObjMesh& mesh,
                    const MeshEncoding& encoding, const std::string& name, ObjMesh& out, std::vector<std::string>& notes,
                    std::vector<std::string>* warnings, ObjLoadProgress* progress);

}  // namespace

namespace detail {

// Reads bytes (a glTF's buffers named as files are looked up beside path, when given) in a reader process.
Status importInReaderProcess(const std::string& bytes, const std::string* path, MeshFormat format, const std::string& name,
                        ObjMesh& out, std::vector<std::string>* warnings, ObjLoadProgress* progress) {
    MeshEncoding encoding{format, false, false};
    std::vector<std::string> notes;
    std::string mended;  // a binary STL whose facet count disagrees with its size, mended (checkStl)
    const char* hint = "";
    switch (format) {
        case MeshFormat::Ply: {
            PlyHeader header;
            if (Status s = parsePlyHeader(bytes, name, header); !s) return s;
            if (Status s = checkPlyBody(bytes, name, header); !s) return s;
            encoding = header.encoding;
            notes = header.notes;
            hint = "ply";
            break;
        }
        case MeshFormat::Stl:
            if (Status s = checkStl(bytes, name, encoding, mended, notes); !s) return s;
            hint = "stl";
            break;
        case MeshFormat::Gltf:
            encoding.binary = bytes.compare(0, 4, "glTF") == 0;
            if (Status s = checkGltf(bytes, name, encoding.binary); !s) return s;
            break;
        case MeshFormat::Off: break;  // ASCII only: readOffDocument refuses binary OFF
        case MeshFormat::Obj: return Status::error(name + ": OBJ is read by loadObj");
    }
    Status status;
    std::vector<std::string> childNotes;
    ObjMesh mesh;
    // assimp crashes on some malformed files (a null dereference and a double free in its PLY header handling,
    // found by tests/fuzz/mesh_fuzz) and loops on others (one a binary PLY whose header passed our checks): every
    // file is read in a child process, which sends the mesh back; a crash or a hang costs an error message, not
    // the program. The timeout allows 3 s plus 1 s per MB (a 1M-vertex GLB of 64 MB reads in about 1.2 s, the copy
    // back included).
    const std::string reader = "the " + std::string(meshFormatName(format)) + " reader (" +
                               (format == MeshFormat::Gltf ? "tinygltf" : format == MeshFormat::Off ? "ours" : "assimp") + ")";
    std::string payload;
    const double timeoutSeconds = 3.0 + static_cast<double>(bytes.size()) / 1e6;
    const Status isolated = runIsolated(
        reader,
        [&](IsolatedChannel& channel) {
            const std::function<void(float)> report = [&channel](float f) { channel.progress(f); };
            const Status read = readInThisProcess(mended.empty() ? bytes : mended, path, hint, format, encoding, name, report,
                                                  mesh, childNotes);
            PayloadWriter sent;
            encodePayload(read, childNotes, mesh, sent);
            channel.result(sent.pieces());
        },
        timeoutSeconds, progress, payload);
    if (!isolated) return Status::error(name + ": " + isolated.message);
    if (!decodePayload(payload, status, childNotes, mesh))
        return Status::error(name + ": " + reader + " sent back a damaged result");
    return finishImport(status, childNotes, mesh, encoding, name, out, notes, warnings, progress);
}

}  // namespace detail

namespace {

// The end of every assimp load, in the caller's process: the reader's verdict and notes, then finishMesh.
Status finishImport(const Status& status, const std::vector<std::string>& readerNotes, ObjMesh& mesh,
                    const MeshEncoding& encoding, const std::string& name, ObjMesh& out, std::vector<std::string>& notes,
                    std::vector<std::string>* warnings, ObjLoadProgress* progress) {
    notes.insert(notes.end(), readerNotes.begin(), readerNotes.end());
    if (!status) return status;
    if (Status s = detail::finishMesh(mesh, encoding, name, notes); !s) return s;
    if (progress && progress->cancel.load()) return Status::error(name + ": loading cancelled");
    out = std::move(mesh);
    if (warnings)
        for (const std::string& note : notes) warnings->push_back(name + ": " + note);
    if (progress) progress->fraction = 1.0f;
    return Status::success();
}

}  // namespace

}  // namespace sculpt::io
