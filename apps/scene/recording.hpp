// Reading back a recording.jsonl (format: docs/scenes.md) and checking that it is complete and
// consistent: the header, every frame against the header's bodies and hands, and the end line.
// Used by tests and by tools that replay recordings; fuzzed in fuzz/fuzz_recording.cpp.
#pragma once

#include <cstdint>
#include <istream>
#include <string>

namespace grip::scene {

struct RecordingSummary {
  std::string scene;
  double dt = 0.0;
  int steps = 0;
  int recordEvery = 1;
  int bodies = 0;
  int hands = 0;
  int frames = 0;    // frame lines read (equal to the end line's count)
  int contacts = 0;  // contact entries over all frames
  std::string stateHash;
};

// Throws grip::Error("<origin>:<line>", "...") naming the first problem (malformed JSON, a
// missing or mistyped field, a pose that is not 7 finite numbers, an index out of range,
// frames out of order, no end line, lines after it).
RecordingSummary checkRecording(std::istream& in, const std::string& origin);
RecordingSummary checkRecordingFile(const std::string& path);

}  // namespace grip::scene
