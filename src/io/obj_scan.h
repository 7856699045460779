// The validating pre-pass over OBJ text, run before tinyobjloader sees it (internal to io).
//
// Why a pre-pass: Debian's tinyobjloader 2.0.0rc10 accepts negative indices pointing outside the
// file (CVE-2020-28589), only warns on out-of-range indices, turns junk/nan/inf into 0 without a word
// and is not correctly rounded. The pre-pass follows tinyobjloader's own line splitting and keyword
// rules exactly (so both see the same lines), is strict where tinyobjloader guesses, and remembers
// the line of every face for error messages. Where the OBJ format allows more than tinyobjloader
// reads (lines continued with a trailing backslash, faces of more than 255 corners), the pre-pass
// reads it and hands tinyobjloader an equivalent text (continuations joined, such faces commented out).
#pragma once

#include <string>
#include <vector>

#include "core/status.h"

namespace sculpt::io {

struct ObjScan {
    std::vector<double> positions;  // 3 per `v` line, correctly rounded (std::from_chars)
    std::vector<double> texcoords;  // 3 per `vt` line, missing components 0
    int texcoordComponents = 2;     // 3 if any `vt` line had a w
    int normalCount = 0;            // number of `vn` lines (values are validated, not kept)

    // Byte ranges in the text of the numbers a writer may replace (offsets are the same in the original
    // text and in sanitizedText): 2 per `v` line, [begin of x, end of z); 2 per `vn` line, likewise.
    std::vector<size_t> positionSpans, normalSpans;

    std::vector<int> faceStart{0};                                // #F + 1
    std::vector<int> cornerVertex, cornerTexcoord, cornerNormal;  // resolved 0-based, -1 = none
    std::vector<int> faceLine;                                    // #F, 1-based line of each face
    std::vector<int> faceGroup;                                   // #F, into groupNames (groupNames[0] = "")
    std::vector<std::string> groupNames{std::string()};
    std::vector<int> faceMaterial;  // #F, into materialNames, -1 = none
    std::vector<std::string> materialNames;
    std::vector<std::string> materialLibraries;
    // The `mtllib` and `usemtl` statements in file order, for reading the .mtl files as tinyobjloader reads
    // them (obj_mesh.cpp): a `mtllib` line's text after the keyword and its blank, or a `usemtl` name.
    struct MaterialStatement {
        size_t line = 0;
        bool library = false;
        std::string text;
    };
    std::vector<MaterialStatement> materialStatements;

    // A copy of the text for tinyobjloader, at the same byte offsets: line continuations (a backslash
    // right before a line break, and the line break) turned into blanks, and the lines tinyobjloader must not
    // interpret turned into comments (`l`, `p`, `t`, `vw`, faces of more than 255 corners, trailing
    // `# ...` on face lines, a UTF-8 byte order mark). Empty when the original text can be handed over
    // as is, which is the usual case (no copy of a large file), and always unless the scan was asked for it
    // (tinyobjCopy: the loader parses once and never hands the text to tinyobjloader).
    std::string sanitizedText;
    std::vector<int> facesNotForTinyobj;  // ascending: faces commented out in sanitizedText (> 255 corners;
                                          // tinyobjloader counts corners in a byte)
    std::vector<std::string> warnings;  // already prefixed with the display name
};

// Collapses runs of spaces/tabs to one space and trims them at both ends: the group name tinyobjloader
// would produce for a `g` line, applied to `o` names too so both read back the same after writing.
std::string normalizeObjName(const std::string& name);

struct ObjLoadProgress;  // obj_mesh.h

// Scans text; on success fills scan (which must be default-constructed). Errors read
// "<displayName>:<line>: <what is wrong>", the line being where the statement starts (a continued
// statement spans several lines). Never throws except std::bad_alloc.
// progress (may be null): fraction raised from 0 to progressEnd as the text is read, every MiB; a cancel
// request stops the scan with "<displayName>: loading cancelled". tinyobjCopy: fill scan.sanitizedText.
Status scanObjText(const std::string& text, const std::string& displayName, ObjScan& scan,
                   ObjLoadProgress* progress = nullptr, float progressEnd = 1.0f, bool tinyobjCopy = false);

// Parses one number token of a `v`/`vt`/`vn` line: [+-]digits[.digits][(e|E)[+-]digits], the whole
// token, finite and within double range. Exposed for tests.
bool parseObjNumber(const char* begin, const char* end, double& value);

}  // namespace sculpt::io
