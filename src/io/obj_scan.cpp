// The validating OBJ pre-pass. It mirrors tinyobjloader 2.0.0rc10's LoadObj (tiny_obj_loader.h):
// lines end at "\n", "\r\n" or a lone "\r" (safeGetline); leading spaces/tabs are skipped; keywords
// are recognised by the same tests in the same order (`v`+blank, `vn`+blank, `vt`+blank, `vw`+blank,
// `l`, `p`, `f`, "usemtl" as a bare prefix, "mtllib"+blank, `g`, `o`, `t`, `s`); tokens are split on
// spaces and tabs only. Where tinyobjloader would guess (atoi, a number parser that maps junk to 0),
// the pre-pass reports an error with the line number instead.
//
// Line continuation (Wavefront's OBJ specification: a backslash at the end of a line continues it on
// the next): joined before anything else looks at the text, on every kind of line, comments included,
// by turning the backslash and the line break after it into blanks, so every byte keeps its offset (as
// Blender's OBJ importer joins them). A backslash followed by anything else, blanks included, is no
// continuation, which lets the writer end a name in a backslash safely ("g a\ "). A backslash ending
// the file continues onto nothing. Error messages give the line a statement starts on.
#include "io/obj_scan.h"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cstdio>
#include <cstring>
#include <system_error>
#include <unordered_map>

#include "io/obj_mesh.h"

namespace sculpt::io {

namespace {

inline bool isBlank(char c) { return c == ' ' || c == '\t'; }
inline bool isDigit(char c) { return c >= '0' && c <= '9'; }

// The next space/tab separated token of [p, end); false when only blanks are left.
inline bool nextToken(const char*& p, const char* end, const char*& tokenBegin, const char*& tokenEnd) {
    while (p < end && isBlank(*p)) ++p;
    if (p == end) return false;
    tokenBegin = p;
    while (p < end && !isBlank(*p)) ++p;
    tokenEnd = p;
    return true;
}

// A token as it may appear in a message: at most 40 bytes, non-printable bytes as '?'.
std::string quoted(const char* begin, const char* end) {
    std::string s = "'";
    const size_t length = static_cast<size_t>(end - begin);
    for (size_t i = 0; i < length && i < 40; ++i) {
        const unsigned char c = static_cast<unsigned char>(begin[i]);
        s += (c < 0x20 || c == 0x7f) ? '?' : static_cast<char>(c);
    }
    if (length > 40) s += "...";
    return s + "'";
}

enum class NumberResult { ok, malformed, outOfRange };

NumberResult parseNumber(const char* begin, const char* end, double& value) {
    const char* p = begin;
    // note: std::from_chars is correctly rounded (libstdc++ 12 uses fast_float) and, unlike strtod,
    // independent of the C locale and never skips leading white space. It does not take a '+' sign,
    // and it does take "inf"/"nan"/hex forms, so the grammar is checked here first.
    if (p < end && (*p == '+' || *p == '-')) ++p;
    if (p == end || !(isDigit(*p) || *p == '.')) return NumberResult::malformed;
    for (const char* q = p; q < end; ++q)
        if (!(isDigit(*q) || *q == '.' || *q == 'e' || *q == 'E' || *q == '+' || *q == '-'))
            return NumberResult::malformed;
    const char* start = (*begin == '+') ? begin + 1 : begin;
    double parsed = 0.0;
    const std::from_chars_result result = std::from_chars(start, end, parsed, std::chars_format::general);
    if (result.ec == std::errc::result_out_of_range) return NumberResult::outOfRange;
    if (result.ec != std::errc() || result.ptr != end) return NumberResult::malformed;
    value = parsed;
    return NumberResult::ok;
}

enum class IndexResult { ok, malformed, zero };

// [-]digits as a whole token. Values beyond int range are clamped to +-(INT_MAX + 1LL) so that the
// range check reports them instead of wrapping like atoi.
IndexResult parseIndex(const char* begin, const char* end, long long& value) {
    const char* p = begin;
    const bool negative = p < end && *p == '-';
    if (negative) ++p;
    if (p == end) return IndexResult::malformed;
    long long magnitude = 0;
    for (; p < end; ++p) {
        if (!isDigit(*p)) return IndexResult::malformed;
        if (magnitude <= INT_MAX) magnitude = magnitude * 10 + (*p - '0');
    }
    if (magnitude > INT_MAX) magnitude = INT_MAX + 1LL;
    if (magnitude == 0) return IndexResult::zero;
    value = negative ? -magnitude : magnitude;
    return IndexResult::ok;
}

class Scanner {
public:
    Scanner(const std::string& text, const std::string& displayName, ObjScan& scan, ObjLoadProgress* progress,
            float progressEnd, bool tinyobjCopy)
        : text_(text), base_(&text), name_(displayName), scan_(scan), progress_(progress), progressEnd_(progressEnd),
          tinyobjCopy_(tinyobjCopy) {}

    Status run();

private:
    Status error(const std::string& what) const {
        return Status::error(name_ + ":" + std::to_string(line_) + ": " + what);
    }
    Status fileError(const std::string& what) const { return Status::error(name_ + ": " + what); }
    void warn(const std::string& what) { scan_.warnings.push_back(name_ + ": " + what); }

    // The edits below go to the sanitized copy for tinyobjloader (copied from the base text on first use), and
    // only when it was asked for: they never change what this scan reads.
    char* editable(const char* p) {
        if (scan_.sanitizedText.empty()) scan_.sanitizedText = *base_;
        return &scan_.sanitizedText[offset(p)];
    }
    size_t offset(const char* p) const { return static_cast<size_t>(p - base_->data()); }
    // Blanks [p, end) in the copy (a trailing comment, a byte order mark).
    void blankOut(const char* p, const char* end) {
        if (!tinyobjCopy_) return;
        char* q = editable(p);
        for (ptrdiff_t i = 0; i < end - p; ++i) q[i] = ' ';
    }
    // Turns a whole statement into a comment line in the copy.
    void commentOut(const char* p, const char* end) {
        blankOut(p, end);
        if (tinyobjCopy_) editable(p)[0] = '#';
    }

    void joinContinuations();
    void reserve(const char* p, const char* end);
    Status line(const char* p, const char* end);
    Status numbers(const char* p, const char* end, const char* keyword, double* values, int maxCount, int& count);
    Status face(const char* statement, const char* p, const char* end);
    Status corner(const char* begin, const char* end, int& v, int& vt, int& vn);
    Status resolve(long long index, int definedSoFar, const char* what, int& resolved);
    void group(const char* p, const char* end);
    void material(const char* p, const char* end);
    void library(const char* p, const char* end);
    void ignored(const char* keywordBegin, const char* keywordEnd, const char* lineEnd, bool mustComment);
    Status finish();

    const std::string& text_;     // the file as given
    std::string joined_;          // text_ with its line continuations blanked; empty if it has none
    const std::string* base_;     // what is scanned: joined_ if there were continuations, else text_
    std::vector<size_t> joinedBreaks_;  // ascending offsets of the line breaks blanked in joined_
    const std::string& name_;
    ObjScan& scan_;
    ObjLoadProgress* progress_;  // may be null
    float progressEnd_;
    bool tinyobjCopy_;  // fill scan_.sanitizedText
    static constexpr ptrdiff_t kProgressStep = 1 << 20;
    size_t line_ = 0;
    const char* spanBegin_ = nullptr;  // numbers(): start of the first and end of the third number
    const char* spanEnd_ = nullptr;
    std::vector<int> sortedCorners_;   // face(): scratch for the repeated-vertex check

    std::string groupName_;  // current `g`/`o` name, normalized
    int groupIndex_ = 0;     // its index in groupNames, -1 until a face uses it
    std::unordered_map<std::string, int> groupIndices_{{std::string(), 0}};
    std::string materialName_;
    int materialIndex_ = -1;  // -1 = none or not yet resolved (see materialResolved_)
    bool materialResolved_ = true;
    std::unordered_map<std::string, int> materialIndices_;

    // Positive indices are checked once the whole file is read (forward references are legal).
    int maxVertex_ = -1, maxTexcoord_ = -1, maxNormal_ = -1;
    size_t repeatedCornerFaces_ = 0, firstRepeatedCornerLine_ = 0;
    size_t ignoredElements_ = 0, firstIgnoredElementLine_ = 0;
    size_t ignoredStatements_ = 0, firstIgnoredStatementLine_ = 0;
    std::string firstIgnoredStatement_;
};

void Scanner::joinContinuations() {
    const char* const data = text_.data();
    const size_t size = text_.size();
    const void* backslash = std::memchr(data, '\\', size);
    if (!backslash) return;  // the usual case: no copy
    for (size_t at = static_cast<size_t>(static_cast<const char*>(backslash) - data); at < size;) {
        size_t after = at + 1;
        const bool atLineEnd = after == size || data[after] == '\n' || data[after] == '\r';
        if (atLineEnd) {
            size_t blankEnd = after;
            if (after < size) {
                joinedBreaks_.push_back(after);
                blankEnd += (data[after] == '\r' && after + 1 < size && data[after + 1] == '\n') ? 2 : 1;
            }
            if (joined_.empty()) joined_ = text_;
            std::fill(joined_.begin() + static_cast<std::ptrdiff_t>(at), joined_.begin() + static_cast<std::ptrdiff_t>(blankEnd),
                      ' ');
            after = blankEnd;
        }
        if (after >= size) break;
        const void* next = std::memchr(data + after, '\\', size - after);
        if (!next) break;
        at = static_cast<size_t>(static_cast<const char*>(next) - data);
    }
    if (!joined_.empty()) base_ = &joined_;
}

Status Scanner::run() {
    if (text_.empty()) return fileError("the file is empty");
    joinContinuations();
    const char* begin = base_->data();
    const char* const end = begin + base_->size();

    const auto* bytes = reinterpret_cast<const unsigned char*>(begin);
    if (text_.size() >= 2 && ((bytes[0] == 0xff && bytes[1] == 0xfe) || (bytes[0] == 0xfe && bytes[1] == 0xff))) {
        line_ = 1;
        return error("the file is UTF-16 encoded (byte order mark); save it as UTF-8 or ASCII");
    }
    if (text_.size() >= 3 && bytes[0] == 0xef && bytes[1] == 0xbb && bytes[2] == 0xbf) {
        // tinyobjloader would read "\xEF\xBB\xBFv" as an unknown keyword and drop the first vertex.
        blankOut(begin, begin + 3);
        begin += 3;
    }

    reserve(begin, end);
    const char* p = begin;
    size_t nextBreak = 0;  // into joinedBreaks_
    const char* nextReport = progress_ ? p + kProgressStep : end;
    while (p < end) {
        if (p >= nextReport) {
            if (progress_->cancel.load(std::memory_order_relaxed)) return fileError("loading cancelled");
            const double done = static_cast<double>(p - begin) / static_cast<double>(end - begin);
            progress_->fraction.store(static_cast<float>(done) * progressEnd_, std::memory_order_relaxed);
            nextReport = p + kProgressStep;
        }
        ++line_;
        const char* lineBegin = p;
        // One pass finds the line end and rejects binary data. note: this is the hot loop for large
        // files; it allocates nothing.
        while (p < end) {
            const unsigned char c = static_cast<unsigned char>(*p);
            if (c < 0x20 || c == 0x7f) {
                if (c == '\n' || c == '\r') break;
                if (c == 0)
                    return error("NUL byte: the file looks like UTF-16 text or binary data, not an OBJ text file");
                if (c != '\t' && c != '\f' && c != '\v') {
                    char hex[8];
                    std::snprintf(hex, sizeof hex, "0x%02x", c);
                    return error(std::string("control byte ") + hex +
                                 ": the file looks like binary data, not OBJ text");
                }
            }
            ++p;
        }
        const char* lineEnd = p;
        if (p < end) p += (*p == '\r' && p + 1 < end && p[1] == '\n') ? 2 : 1;
        Status status = line(lineBegin, lineEnd);
        if (!status) return status;
        // The physical lines this statement was continued over.
        while (nextBreak < joinedBreaks_.size() && joinedBreaks_[nextBreak] < offset(lineEnd)) {
            ++nextBreak;
            ++line_;
        }
    }
    Status finished = finish();
    if (finished && tinyobjCopy_ && scan_.sanitizedText.empty() && !joined_.empty()) scan_.sanitizedText = std::move(joined_);
    return finished;
}

// note: a quick count of `v`, `vt` and `f` lines (memchr per line, no parsing) so the arrays are
// allocated once: on a 1M-vertex file, growing them by doubling cost more than this pass, mostly in
// page faults and copies. Triangles are assumed; polygon files grow the corner arrays once or twice.
void Scanner::reserve(const char* p, const char* end) {
    size_t vertices = 0, texcoords = 0, faces = 0;
    while (p < end) {
        while (p < end && isBlank(*p)) ++p;
        if (end - p >= 2 && isBlank(p[1])) {
            vertices += *p == 'v';
            faces += *p == 'f';
        } else if (end - p >= 3 && p[0] == 'v' && p[1] == 't' && isBlank(p[2])) {
            ++texcoords;
        }
        const void* newline = std::memchr(p, '\n', static_cast<size_t>(end - p));
        p = newline ? static_cast<const char*>(newline) + 1 : end;
    }
    scan_.positions.reserve(3 * vertices);
    scan_.positionSpans.reserve(2 * vertices);
    scan_.texcoords.reserve(3 * texcoords);
    scan_.faceStart.reserve(faces + 1);
    for (std::vector<int>* corners : {&scan_.cornerVertex, &scan_.cornerTexcoord, &scan_.cornerNormal})
        corners->reserve(3 * faces);
    for (std::vector<int>* perFace : {&scan_.faceLine, &scan_.faceGroup, &scan_.faceMaterial}) perFace->reserve(faces);
}

Status Scanner::line(const char* p, const char* end) {
    while (p < end && isBlank(*p)) ++p;
    if (p == end || *p == '#') return Status::success();
    const ptrdiff_t n = end - p;
    auto blankAt = [&](ptrdiff_t i) { return i < n && isBlank(p[i]); };

    if (p[0] == 'v' && blankAt(1)) {
        if (scan_.positions.size() / 3 >= static_cast<size_t>(INT_MAX)) return error("too many vertices");
        double xyz[7];
        int count = 0;
        Status status = numbers(p + 2, end, "v", xyz, 7, count);
        if (!status) return status;
        if (count < 3) return error("a 'v' line needs x y z (found " + std::to_string(count) + " numbers)");
        scan_.positions.insert(scan_.positions.end(), xyz, xyz + 3);
        scan_.positionSpans.insert(scan_.positionSpans.end(), {offset(spanBegin_), offset(spanEnd_)});
        return Status::success();
    }
    if (p[0] == 'v' && n >= 2 && p[1] == 'n' && blankAt(2)) {
        if (scan_.normalCount == INT_MAX) return error("too many normals");
        double xyz[3];
        int count = 0;
        Status status = numbers(p + 3, end, "vn", xyz, 3, count);
        if (!status) return status;
        if (count != 3) return error("a 'vn' line needs x y z (found " + std::to_string(count) + " numbers)");
        ++scan_.normalCount;
        scan_.normalSpans.insert(scan_.normalSpans.end(), {offset(spanBegin_), offset(spanEnd_)});
        return Status::success();
    }
    if (p[0] == 'v' && n >= 2 && p[1] == 't' && blankAt(2)) {
        if (scan_.texcoords.size() / 3 >= static_cast<size_t>(INT_MAX)) return error("too many texture coordinates");
        double uvw[3] = {0.0, 0.0, 0.0};
        int count = 0;
        Status status = numbers(p + 3, end, "vt", uvw, 3, count);
        if (!status) return status;
        if (count < 1) return error("a 'vt' line needs u [v [w]] (found no numbers)");
        if (count == 3) scan_.texcoordComponents = 3;
        scan_.texcoords.insert(scan_.texcoords.end(), uvw, uvw + 3);
        return Status::success();
    }
    if (p[0] == 'v' && n >= 2 && p[1] == 'w' && blankAt(2)) {
        ignored(p, p + 2, end, true);  // tinyobjloader's skin-weight extension; it fails on some of them
        return Status::success();
    }
    if ((p[0] == 'l' || p[0] == 'p') && blankAt(1)) {
        // Line and point elements are not part of the surface; commented out so tinyobjloader does
        // not resolve their (unchecked) indices.
        commentOut(p, end);
        if (ignoredElements_++ == 0) firstIgnoredElementLine_ = line_;
        return Status::success();
    }
    if (p[0] == 'f' && blankAt(1)) return face(p, p + 2, end);
    if (n >= 6 && std::memcmp(p, "usemtl", 6) == 0) {
        material(p + 6, end);
        return Status::success();
    }
    if (n >= 6 && std::memcmp(p, "mtllib", 6) == 0 && blankAt(6)) {
        library(p + 7, end);
        return Status::success();
    }
    if ((p[0] == 'g' || p[0] == 'o') && blankAt(1)) {
        group(p + 2, end);
        return Status::success();
    }
    if (p[0] == 't' && blankAt(1)) {
        // note: tinyobjloader's subdivision tags allocate up to 3 x 8192 values per line and copy all of
        // them into every shape; a small hostile file could exhaust memory. Not used here, so removed.
        ignored(p, p + 1, end, true);
        return Status::success();
    }
    if (p[0] == 's' && blankAt(1)) return Status::success();  // smoothing groups: normals are recomputed
    const char* keywordEnd = p;
    while (keywordEnd < end && !isBlank(*keywordEnd)) ++keywordEnd;
    ignored(p, keywordEnd, end, false);
    return Status::success();
}

void Scanner::ignored(const char* keywordBegin, const char* keywordEnd, const char* lineEnd, bool mustComment) {
    if (mustComment) commentOut(keywordBegin, lineEnd);
    if (ignoredStatements_++ == 0) {
        firstIgnoredStatementLine_ = line_;
        firstIgnoredStatement_ = quoted(keywordBegin, keywordEnd);
    }
}

Status Scanner::numbers(const char* p, const char* end, const char* keyword, double* values, int maxCount, int& count) {
    const char* tokenBegin;
    const char* tokenEnd;
    count = 0;
    while (nextToken(p, end, tokenBegin, tokenEnd)) {
        if (*tokenBegin == '#') break;  // trailing comment
        if (count == maxCount)
            return error(std::string("too many numbers in a '") + keyword + "' line (at most " +
                         std::to_string(maxCount) + ")");
        switch (parseNumber(tokenBegin, tokenEnd, values[count])) {
            case NumberResult::ok:
                if (count == 0) spanBegin_ = tokenBegin;
                if (count == 2) spanEnd_ = tokenEnd;
                break;
            case NumberResult::malformed:
                return error(quoted(tokenBegin, tokenEnd) + " in a '" + keyword +
                             "' line is not a finite decimal number");
            case NumberResult::outOfRange:
                return error(quoted(tokenBegin, tokenEnd) + " in a '" + keyword +
                             "' line is out of the range of a double");
        }
        ++count;
    }
    return Status::success();
}

Status Scanner::resolve(long long index, int definedSoFar, const char* what, int& resolved) {
    if (index > 0) {
        // Checked against the final count in finish(); INT_MAX + 1 maps to a value finish() rejects.
        resolved = index > INT_MAX ? INT_MAX : static_cast<int>(index - 1);
        return Status::success();
    }
    const long long relative = definedSoFar + index;  // OBJ: -1 is the last one defined so far
    if (relative < 0)
        return error(std::string("relative ") + what + " index " + std::to_string(index) +
                     " points before the first one (" + std::to_string(definedSoFar) + " defined so far)");
    resolved = static_cast<int>(relative);
    return Status::success();
}

Status Scanner::corner(const char* begin, const char* end, int& v, int& vt, int& vn) {
    // v, v/vt, v//vn or v/vt/vn
    const char* part[3] = {begin, nullptr, nullptr};
    const char* partEnd[3] = {end, nullptr, nullptr};
    int parts = 1;
    for (const char* q = begin; q < end; ++q) {
        if (*q != '/') continue;
        if (parts == 3) return error("bad face corner " + quoted(begin, end) + " (more than two '/')");
        partEnd[parts - 1] = q;
        part[parts] = q + 1;
        partEnd[parts] = end;
        ++parts;
    }
    static const char* const kWhat[3] = {"face", "texture coordinate", "normal"};
    const int defined[3] = {static_cast<int>(scan_.positions.size() / 3), static_cast<int>(scan_.texcoords.size() / 3),
                            scan_.normalCount};
    int resolved[3] = {-1, -1, -1};
    for (int i = 0; i < parts; ++i) {
        if (part[i] == partEnd[i] && i == 1 && parts == 3) continue;  // v//vn
        long long index = 0;
        switch (parseIndex(part[i], partEnd[i], index)) {
            case IndexResult::ok:
                break;
            case IndexResult::zero:
                return error(std::string(kWhat[i]) + " index 0 in " + quoted(begin, end) +
                             " is invalid (OBJ indices start at 1)");
            case IndexResult::malformed:
                return error("bad face corner " + quoted(begin, end) +
                             " (expected v, v/vt, v//vn or v/vt/vn with integer indices)");
        }
        Status status = resolve(index, defined[i], kWhat[i], resolved[i]);
        if (!status) return status;
    }
    v = resolved[0];
    vt = resolved[1];
    vn = resolved[2];
    return Status::success();
}

Status Scanner::face(const char* statement, const char* p, const char* end) {
    const int cornerBegin = scan_.faceStart.back();
    const char* tokenBegin;
    const char* tokenEnd;
    int corners = 0;
    while (nextToken(p, end, tokenBegin, tokenEnd)) {
        if (*tokenBegin == '#') {
            blankOut(tokenBegin, end);  // tinyobjloader would read '#' as index 0 and fail
            break;
        }
        if (scan_.cornerVertex.size() >= static_cast<size_t>(INT_MAX - 1)) return error("too many face corners");
        int v, vt, vn;
        Status status = corner(tokenBegin, tokenEnd, v, vt, vn);
        if (!status) return status;
        scan_.cornerVertex.push_back(v);
        scan_.cornerTexcoord.push_back(vt);
        scan_.cornerNormal.push_back(vn);
        maxVertex_ = std::max(maxVertex_, v);
        maxTexcoord_ = std::max(maxTexcoord_, vt);
        maxNormal_ = std::max(maxNormal_, vn);
        ++corners;
    }
    if (corners < 3) return error("a face needs at least 3 corners (found " + std::to_string(corners) + ")");
    // note: tinyobjloader stores corner counts in an unsigned char, so a larger face would wrap there; it
    // is kept from tinyobjloader (commented out in its copy) and checkAgreement leaves it out.
    if (corners > 255) {
        commentOut(statement, end);
        scan_.facesNotForTinyobj.push_back(static_cast<int>(scan_.faceLine.size()));
    }
    // A vertex used twice makes a degenerate triangle; worth a warning, not an error. note: a sorted copy
    // in reused scratch, so a face costs n log n and, after the first large one, no allocation.
    sortedCorners_.assign(scan_.cornerVertex.begin() + cornerBegin, scan_.cornerVertex.end());
    std::sort(sortedCorners_.begin(), sortedCorners_.end());
    if (std::adjacent_find(sortedCorners_.begin(), sortedCorners_.end()) != sortedCorners_.end() &&
        repeatedCornerFaces_++ == 0)
        firstRepeatedCornerLine_ = line_;

    if (groupIndex_ < 0) {
        const auto inserted = groupIndices_.emplace(groupName_, static_cast<int>(scan_.groupNames.size()));
        if (inserted.second) scan_.groupNames.push_back(groupName_);
        groupIndex_ = inserted.first->second;
    }
    if (!materialResolved_) {
        const auto inserted = materialIndices_.emplace(materialName_, static_cast<int>(scan_.materialNames.size()));
        if (inserted.second) scan_.materialNames.push_back(materialName_);
        materialIndex_ = inserted.first->second;
        materialResolved_ = true;
    }
    scan_.faceStart.push_back(cornerBegin + corners);
    scan_.faceLine.push_back(static_cast<int>(std::min<size_t>(line_, INT_MAX)));
    scan_.faceGroup.push_back(groupIndex_);
    scan_.faceMaterial.push_back(materialIndex_);
    return Status::success();
}

void Scanner::group(const char* p, const char* end) {
    // tinyobjloader joins the names of a `g` line with single spaces and takes an `o` line verbatim;
    // both end up as the normalized name.
    groupName_.clear();
    const char* tokenBegin;
    const char* tokenEnd;
    while (nextToken(p, end, tokenBegin, tokenEnd)) {
        if (!groupName_.empty()) groupName_ += ' ';
        groupName_.append(tokenBegin, tokenEnd);
    }
    groupIndex_ = -1;
}

void Scanner::material(const char* p, const char* end) {
    // As tinyobjloader: the first token after "usemtl" ("usemtlfoo" names "foo").
    const char* tokenBegin;
    const char* tokenEnd;
    const bool named = nextToken(p, end, tokenBegin, tokenEnd);
    scan_.materialStatements.push_back({line_, false, named ? std::string(tokenBegin, tokenEnd) : std::string()});
    if (named) {
        materialName_.assign(tokenBegin, tokenEnd);
        materialResolved_ = false;
    } else {
        materialIndex_ = -1;  // an empty `usemtl` means no material, as writeObj emits it
        materialResolved_ = true;
    }
}

void Scanner::library(const char* p, const char* end) {
    scan_.materialStatements.push_back({line_, true, std::string(p, end)});
    while (p < end && isBlank(*p)) ++p;
    while (end > p && isBlank(end[-1])) --end;
    if (p == end) {
        warn("line " + std::to_string(line_) + ": 'mtllib' without a file name");
        return;
    }
    std::string name(p, end);
    for (const std::string& known : scan_.materialLibraries)
        if (known == name) return;
    scan_.materialLibraries.push_back(std::move(name));
}

Status Scanner::finish() {
    const int vertexCount = static_cast<int>(scan_.positions.size() / 3);
    const int texcoordCount = static_cast<int>(scan_.texcoords.size() / 3);
    const int faceCount = static_cast<int>(scan_.faceLine.size());
    if (vertexCount == 0) return fileError("no vertices ('v' lines) found; is this an OBJ file?");
    if (faceCount == 0)
        return fileError(ignoredElements_ > 0 ? "no faces ('f' lines) found, only line/point elements"
                                              : "no faces ('f' lines) found");

    struct Check {
        const std::vector<int>& corners;
        int max;
        int count;
        const char* what;
        const char* plural;
    };
    const Check checks[3] = {
        {scan_.cornerVertex, maxVertex_, vertexCount, "face", "vertices"},
        {scan_.cornerTexcoord, maxTexcoord_, texcoordCount, "texture coordinate", "texture coordinates"},
        {scan_.cornerNormal, maxNormal_, scan_.normalCount, "normal", "normals"}};
    for (const Check& check : checks) {
        if (check.max < check.count) continue;
        // Report the first offending corner in file order.
        for (int f = 0; f < faceCount; ++f)
            for (int c = scan_.faceStart[f]; c < scan_.faceStart[f + 1]; ++c)
                if (check.corners[c] >= check.count) {
                    line_ = static_cast<size_t>(scan_.faceLine[f]);
                    const std::string index = check.corners[c] == INT_MAX ? std::string("beyond 2^31")
                                                                          : std::to_string(check.corners[c] + 1LL);
                    return error(std::string(check.what) + " index " + index + " is out of range (file has " +
                                 std::to_string(check.count) + " " + check.plural + ")");
                }
    }

    // Nothing is dropped: a save writes these lines back unchanged (ObjMesh::source).
    if (ignoredElements_ > 0)
        warn(std::to_string(ignoredElements_) + " line/point element(s) not shown, kept in the file (first on line " +
             std::to_string(firstIgnoredElementLine_) + ")");
    if (ignoredStatements_ > 0)
        warn(std::to_string(ignoredStatements_) + " statement(s) the sculptor does not use, kept in the file " +
             "(first on line " + std::to_string(firstIgnoredStatementLine_) + ": " + firstIgnoredStatement_ + ")");
    if (repeatedCornerFaces_ > 0)
        warn(std::to_string(repeatedCornerFaces_) + " face(s) use a vertex twice (first on line " +
             std::to_string(firstRepeatedCornerLine_) + ")");
    std::vector<char> used(static_cast<size_t>(vertexCount), 0);
    for (int v : scan_.cornerVertex) used[static_cast<size_t>(v)] = 1;
    size_t unused = 0;
    for (char u : used) unused += u ? 0 : 1;
    if (unused > 0) warn(std::to_string(unused) + " vertex/vertices not used by any face");
    return Status::success();
}

}  // namespace

std::string normalizeObjName(const std::string& name) {
    std::string normalized;
    const char* p = name.data();
    const char* const end = p + name.size();
    const char* tokenBegin;
    const char* tokenEnd;
    while (nextToken(p, end, tokenBegin, tokenEnd)) {
        if (!normalized.empty()) normalized += ' ';
        normalized.append(tokenBegin, tokenEnd);
    }
    return normalized;
}

Status scanObjText(const std::string& text, const std::string& displayName, ObjScan& scan, ObjLoadProgress* progress,
                   float progressEnd, bool tinyobjCopy) {
    return Scanner(text, displayName, scan, progress, progressEnd, tinyobjCopy).run();
}

bool parseObjNumber(const char* begin, const char* end, double& value) {
    return parseNumber(begin, end, value) == NumberResult::ok;
}

}  // namespace sculpt::io
