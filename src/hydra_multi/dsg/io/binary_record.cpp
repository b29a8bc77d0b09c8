#include "hydra_multi/dsg/io/binary_record.h"

#include "hydra_multi/dsg/io/byte_codec.h"
#include "hydra_multi/dsg/io/decode_error.h"

namespace hydra_multi::io {
namespace {

constexpr std::string_view kMagic = "HMDG";

}  // namespace

std::string encodeRecord(RecordKind kind, const std::string& payload) {
  ByteWriter body;
  body.u8(static_cast<uint8_t>(kind));
  body.u16(kBinaryVersion);
  body.varint(payload.size());
  body.raw(payload);
  ByteWriter record;
  record.raw(kMagic);
  record.raw(body.bytes());
  record.u32(crc32(body.bytes()));
  return record.release();
}

size_t recordSize(size_t payload_size) {
  ByteWriter header;  // as encodeRecord's body, before the payload
  header.u8(0);
  header.u16(kBinaryVersion);
  header.varint(payload_size);
  return kMagic.size() + header.bytes().size() + payload_size + sizeof(uint32_t);
}

Result<std::optional<RecordView>> RecordReader::next() {
  broken_.reset();
  if (pos_ == bytes_.size()) return std::optional<RecordView>();
  const size_t start = pos_;
  ByteReader reader(bytes_.substr(pos_), pos_);
  try {
    if (reader.raw(kMagic.size(), "record magic") != kMagic) {
      reader.fail("not a hydra-multi binary record (magic bytes are not \"HMDG\")");
    }
    const size_t body_start = reader.offset() - start;
    const uint8_t kind = reader.u8("record kind");
    if (kind < 1 || kind > 3) reader.fail("unknown record kind " + std::to_string(kind));
    const uint16_t version = reader.u16("format version");
    if (version != kBinaryVersion) {
      reader.fail("format version " + std::to_string(version) +
                  " is not supported (this build reads " + std::to_string(kBinaryVersion) + ")");
    }
    const uint64_t size = reader.varint("payload size");
    if (size > reader.remaining()) {
      reader.fail("payload of " + std::to_string(size) + " bytes is longer than the " +
                  std::to_string(reader.remaining()) + " bytes left: truncated");
    }
    const std::string_view payload = reader.raw(static_cast<size_t>(size), "payload");
    const size_t body_end = reader.offset() - start;
    const uint32_t stored = reader.u32("checksum");
    const uint32_t computed = crc32(bytes_.substr(start + body_start, body_end - body_start));
    if (stored != computed) reader.fail("checksum mismatch: the record is corrupt");
    pos_ = reader.offset();
    return std::optional<RecordView>(RecordView{static_cast<RecordKind>(kind), start, payload});
  } catch (const DecodeError& error) {
    pos_ = bytes_.size();  // nothing after a broken record can be trusted to start a record
    broken_ = start;
    return Error{std::string("record at byte ") + std::to_string(start) + ": " + error.what()};
  }
}

std::optional<size_t> RecordReader::resynchronize() {
  if (!broken_) return std::nullopt;
  const size_t found = bytes_.find(kMagic, *broken_ + 1);
  broken_.reset();
  if (found == std::string_view::npos) return std::nullopt;
  pos_ = found;
  return found;
}

}  // namespace hydra_multi::io
