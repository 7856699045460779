#include "app/document.h"

#include <cstring>

namespace sculpt::app {
namespace {

// FNV-1a over 64-bit words with a final avalanche (splitmix64): cheap, and a collision needs two different
// histories agreeing on 64 bits.
class Fingerprint {
public:
    void add(std::uint64_t word) { hash_ = (hash_ ^ word) * 0x100000001b3ULL; }
    void add(int value) { add(static_cast<std::uint64_t>(static_cast<std::int64_t>(value))); }
    void add(bool value) { add(static_cast<std::uint64_t>(value)); }
    void add(double value) {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &value, sizeof bits);
        add(bits);
    }
    void add(const std::string& text) {
        add(static_cast<std::uint64_t>(text.size()));
        for (unsigned char c : text) add(static_cast<std::uint64_t>(c));
    }
    void add(const Eigen::Vector3d& v) {
        add(v.x());
        add(v.y());
        add(v.z());
    }
    void add(const core::LatticeSettings& s) {
        for (int a = 0; a < 3; ++a) {
            add(s.resolution[a]);
            add(s.degree[a]);
        }
        add(s.padding);
        add(s.pinLayers);
        add(s.hasRegion);
        if (s.hasRegion) {
            add(s.regionMin);
            add(s.regionMax);
        }
    }
    void add(const std::vector<core::PointConstraint>& constraints) {
        add(static_cast<std::uint64_t>(constraints.size()));
        for (const core::PointConstraint& c : constraints) {
            add(c.source);
            add(c.target);
        }
    }
    std::uint64_t value() const {
        std::uint64_t z = hash_ + 0x9e3779b97f4a7c15ULL;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }

private:
    std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

// What identifies an operation of the history (its label, kind, user input and step count).
void addOperation(Fingerprint& f, const core::Operation& op) {
    f.add(static_cast<int>(op.kind));
    f.add(op.label);
    f.add(op.interactive);
    f.add(op.constraints);
    f.add(static_cast<std::uint64_t>(op.controlPoints.size()));
    for (int id : op.controlPoints) f.add(id);
    for (Eigen::Index r = 0; r < op.offsets.rows(); ++r) f.add(Eigen::Vector3d(op.offsets.row(r).transpose()));
    f.add(op.settings);
    f.add(static_cast<std::uint64_t>(op.steps.size()));
    f.add(static_cast<std::uint64_t>(op.refinement.splits.size()));
    f.add(static_cast<std::uint64_t>(op.refinementBefore.splits.size()));
    for (const core::Step& step : op.steps) {
        f.add(step.freshFrame);
        f.add(step.constraints);
        f.add(static_cast<std::uint64_t>(step.delta.indices.size()));
        // note: a control-point edit's deltas are its user input (few points); a drag's follow from its
        // constraints, and hashing them would cost per frame what the drag's size costs.
        if (op.kind == core::OperationKind::ControlPointEdit) {
            for (int id : step.delta.indices) f.add(id);
            for (Eigen::Index r = 0; r < step.delta.deltas.rows(); ++r)
                f.add(Eigen::Vector3d(step.delta.deltas.row(r).transpose()));
        }
    }
    f.add(static_cast<std::uint64_t>(op.parts.size()));
    for (const core::Operation& part : op.parts) addOperation(f, part);  // a group kept whole
}

}  // namespace

HistoryMark markHistory(const core::Session& session) {
    HistoryMark mark;
    mark.cursor = session.history().cursor();
    Fingerprint f;
    for (int i = 0; i < mark.cursor; ++i) addOperation(f, session.history()[static_cast<size_t>(i)]);
    mark.fingerprint = f.value();
    return mark;
}

bool isModified(const Document& document, const core::Session& session) {
    return session.stroke().active() || markHistory(session) != document.saved;
}

}  // namespace sculpt::app
