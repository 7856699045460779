// The history on its own (core/session/history.h): random sequences of pushes, undos, redos, groups and notes
// (fixed seed) against a plain model of what they mean: a list, a cursor, and the journal of every command.
#include <catch2/catch.hpp>

#include <random>
#include <string>
#include <vector>

#include "core/session/history.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;

TEST_CASE("history: pushes, undos, redos, groups and notes move the cursor and journal every command", "[core]") {
    std::mt19937 rng(77);
    for (int trial = 0; trial < 20; ++trial) {
        History history;
        std::vector<std::string> labels;  // the model: entries by label
        int cursor = 0;
        std::vector<JournalEntry::Kind> journal;
        int next = 0;
        for (int command = 0; command < 60; ++command) {
            const int kind = test::randomInt(rng, 0, 5);
            if (kind <= 1) {  // push: the redo branch goes
                Operation operation;
                operation.label = "op " + std::to_string(next++);
                history.push(operation);
                labels.resize(static_cast<size_t>(cursor));
                labels.push_back(operation.label);
                cursor = static_cast<int>(labels.size());
                journal.push_back(JournalEntry::Kind::Operation);
            } else if (kind == 2 && cursor > 0) {
                CHECK(history.stepBack().label == labels[static_cast<size_t>(--cursor)]);
                journal.push_back(JournalEntry::Kind::Undo);
            } else if (kind == 3 && cursor < static_cast<int>(labels.size())) {
                CHECK(history.stepForward().label == labels[static_cast<size_t>(cursor++)]);
                journal.push_back(JournalEntry::Kind::Redo);
            } else if (kind == 4 && cursor == static_cast<int>(labels.size()) && cursor > 0) {
                const int first = test::randomInt(rng, 0, cursor - 1);
                Operation merged;
                merged.label = "group from " + std::to_string(first);
                history.replaceTail(first, merged);
                labels.resize(static_cast<size_t>(first));
                labels.push_back(merged.label);
                cursor = static_cast<int>(labels.size());
                journal.push_back(JournalEntry::Kind::Group);
                CHECK(history.journal().back().groupFirst == first);
                CHECK(history.journal().back().label == merged.label);
            } else if (kind == 5) {  // a pin change: consecutive ones are one record
                JournalEntry pins;
                pins.kind = JournalEntry::Kind::Pins;
                pins.pinToggles = {command};
                history.note(pins, true);
                if (journal.empty() || journal.back() != JournalEntry::Kind::Pins) journal.push_back(JournalEntry::Kind::Pins);
                CHECK(history.journal().back().pinToggles == std::vector<int>{command});
            }
            REQUIRE(history.cursor() == cursor);
            REQUIRE(history.entries().size() == labels.size());
            CHECK(history.atEnd() == (cursor == static_cast<int>(labels.size())));
            for (size_t i = 0; i < labels.size(); ++i) CHECK(history.entries()[i].label == labels[i]);
            REQUIRE(history.journal().size() == journal.size());
            for (size_t i = 0; i < journal.size(); ++i) CHECK(history.journal()[i].kind == journal[i]);
        }
        history.clear();
        CHECK(history.entries().empty());
        CHECK(history.journal().empty());
        CHECK(history.cursor() == 0);
    }
}
