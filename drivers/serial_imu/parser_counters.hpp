// Fault and progress counters of a protocol parser, one per kind of event.
//
// Written only by the thread that calls feed() (rt::SingleWriterCounter: relaxed load + store),
// readable from any thread while it runs (exit report, status topic).
// Byte accounting is exact: every byte ever fed is in exactly one of bytes_in_messages,
// resync_bytes_skipped or the parser's pending_bytes().
#pragma once

#include <cstdint>

#include "rt/counters.hpp"

namespace vigs::drivers {

struct ParserCounters {
  rt::SingleWriterCounter bytes_fed;             ///< every byte passed to feed()
  rt::SingleWriterCounter bytes_in_messages;     ///< bytes of checksum-valid messages
  rt::SingleWriterCounter packets_ok;            ///< valid measurement messages -> one sample each
  rt::SingleWriterCounter other_messages;        ///< valid messages of other kinds (ignored)
  rt::SingleWriterCounter bad_checksum;          ///< complete candidates whose checksum failed
  rt::SingleWriterCounter resync_bytes_skipped;  ///< bytes discarded while hunting for a header
  rt::SingleWriterCounter oversize_length;       ///< length field above the protocol maximum
  rt::SingleWriterCounter malformed_payload;     ///< valid checksum, but fields overrun the payload
  rt::SingleWriterCounter incomplete_sample;     ///< valid message lacking time, accel or gyro
  rt::SingleWriterCounter unsupported_format;    ///< known field in a precision we do not decode
  rt::SingleWriterCounter non_finite_sample;     ///< valid message with a NaN/Inf value: dropped
};

}  // namespace vigs::drivers
