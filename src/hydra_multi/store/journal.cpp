#include "hydra_multi/store/journal.h"

#include <sqlite3.h>

namespace hydra_multi::store {
namespace {

constexpr const char* kSchema =
    "CREATE TABLE IF NOT EXISTS updates ("
    " id INTEGER PRIMARY KEY,"
    " robot TEXT NOT NULL,"
    " epoch INTEGER NOT NULL,"
    " sequence INTEGER NOT NULL,"
    " payload BLOB NOT NULL,"
    " arrival_ns INTEGER NOT NULL,"
    " snapshot INTEGER NOT NULL,"
    " wire_bytes INTEGER NOT NULL,"
    " UNIQUE (robot, sequence, snapshot));"
    "CREATE TABLE IF NOT EXISTS done ("
    " robot TEXT PRIMARY KEY,"
    " epoch INTEGER NOT NULL,"
    " last_update INTEGER NOT NULL)";  // the updates' last id when the BYE came

// SQLite integers are signed 64-bit; sequences and epochs are stored bit for bit.
int64_t toSql(uint64_t v) { return static_cast<int64_t>(v); }
uint64_t fromSql(int64_t v) { return static_cast<uint64_t>(v); }

}  // namespace

struct Journal::Impl {
  ~Impl() {
    sqlite3_finalize(insert);
    sqlite3_close(db);
  }
  std::string error(const std::string& what) const {
    return path + ": " + what + ": " + (db ? sqlite3_errmsg(db) : "no database");
  }
  Status exec(const char* sql, const std::string& what) const {
    char* message = nullptr;
    if (sqlite3_exec(db, sql, nullptr, nullptr, &message) == SQLITE_OK) return Status::Ok();
    const std::string text = message ? message : "";
    sqlite3_free(message);
    return Error{path + ": " + what + ": " + text};
  }

  std::string path;
  sqlite3* db = nullptr;
  sqlite3_stmt* insert = nullptr;
};

Result<std::unique_ptr<Journal>> Journal::open(const std::string& path, Durability durability) {
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  if (sqlite3_open_v2(path.c_str(), &impl->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE,
                      nullptr) != SQLITE_OK)
    return Error{impl->error("cannot open the journal")};
  // A file that is not a database shows here, at the first statement that reads it.
  if (Status s = impl->exec("PRAGMA journal_mode=WAL", "not a journal (SQLite)"); !s)
    return Error{s.message()};
  if (Status s = impl->exec(
          durability == Durability::kFull ? "PRAGMA synchronous=FULL" : "PRAGMA synchronous=NORMAL",
          "cannot set its durability");
      !s)
    return Error{s.message()};
  if (Status s = impl->exec(kSchema, "not a journal of robot updates"); !s)
    return Error{s.message()};
  if (sqlite3_prepare_v2(
          impl->db,
          "INSERT INTO updates (robot, epoch, sequence, payload, arrival_ns, snapshot, "
          "wire_bytes) VALUES (?, ?, ?, ?, ?, ?, ?)",
          -1, &impl->insert, nullptr) != SQLITE_OK)
    return Error{impl->error("not a journal of robot updates (its table has other columns)")};
  return std::unique_ptr<Journal>(new Journal(std::move(impl)));
}

Journal::Journal(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Journal::~Journal() = default;

const std::string& Journal::path() const { return impl_->path; }

Status Journal::append(const JournalEntry& e) {
  sqlite3_stmt* s = impl_->insert;
  const std::string robot = e.robot.str();
  sqlite3_bind_text(s, 1, robot.c_str(), static_cast<int>(robot.size()), SQLITE_TRANSIENT);
  sqlite3_bind_int64(s, 2, toSql(e.epoch));
  sqlite3_bind_int64(s, 3, toSql(e.sequence));
  sqlite3_bind_blob64(s, 4, e.payload.data(), e.payload.size(), SQLITE_STATIC);
  sqlite3_bind_int64(s, 5, e.arrival_ns);
  sqlite3_bind_int(s, 6, e.snapshot ? 1 : 0);
  sqlite3_bind_int64(s, 7, static_cast<int64_t>(e.wire_bytes));
  const int rc = sqlite3_step(s);  // autocommit: one transaction
  sqlite3_reset(s);
  sqlite3_clear_bindings(s);
  if (rc == SQLITE_DONE) return Status::Ok();
  if (rc == SQLITE_CONSTRAINT)
    return Error{impl_->path + ": " + (e.snapshot ? "snapshot " : "update ") +
                 std::to_string(e.sequence) + " of robot " + robot + " is in the journal already"};
  return Error{
      impl_->error("cannot append update " + std::to_string(e.sequence) + " of robot " + robot)};
}

Status Journal::replay(const std::function<void(JournalEntry&&)>& each) const {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(
          impl_->db,
          "SELECT robot, epoch, sequence, payload, arrival_ns, snapshot, wire_bytes FROM updates "
          "ORDER BY id",
          -1, &s, nullptr) != SQLITE_OK)
    return Error{impl_->error("cannot read the journal")};
  int rc = SQLITE_ROW;
  size_t row = 0;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    ++row;
    const char* text = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    const auto robot = RobotId::parse(text ? text : "");
    if (!robot) {
      sqlite3_finalize(s);
      return Error{impl_->path + ": row " + std::to_string(row) + ": unknown robot '" +
                   (text ? text : "") + "'"};
    }
    JournalEntry e;
    e.robot = *robot;
    e.epoch = fromSql(sqlite3_column_int64(s, 1));
    e.sequence = fromSql(sqlite3_column_int64(s, 2));
    const void* blob = sqlite3_column_blob(s, 3);
    e.payload.assign(static_cast<const char*>(blob),
                     static_cast<size_t>(sqlite3_column_bytes(s, 3)));
    e.arrival_ns = sqlite3_column_int64(s, 4);
    e.snapshot = sqlite3_column_int(s, 5) != 0;
    e.wire_bytes = static_cast<size_t>(sqlite3_column_int64(s, 6));
    each(std::move(e));
  }
  sqlite3_finalize(s);
  if (rc != SQLITE_DONE) return Error{impl_->error("cannot read the journal")};
  return Status::Ok();
}

Status Journal::markDone(RobotId robot, uint64_t epoch) {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(impl_->db,
                         "INSERT OR REPLACE INTO done (robot, epoch, last_update) "
                         "VALUES (?, ?, (SELECT coalesce(max(id), 0) FROM updates))",
                         -1, &s, nullptr) != SQLITE_OK)
    return Error{impl_->error("cannot record that robot " + robot.str() + " is done")};
  const std::string name = robot.str();
  sqlite3_bind_text(s, 1, name.c_str(), static_cast<int>(name.size()), SQLITE_TRANSIENT);
  sqlite3_bind_int64(s, 2, toSql(epoch));
  const int rc = sqlite3_step(s);
  sqlite3_finalize(s);
  if (rc != SQLITE_DONE)
    return Error{impl_->error("cannot record that robot " + robot.str() + " is done")};
  return Status::Ok();
}

Result<std::map<RobotId, uint64_t>> Journal::done() const {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(impl_->db,
                         "SELECT robot, epoch FROM done WHERE NOT EXISTS (SELECT 1 FROM updates "
                         "WHERE updates.robot = done.robot AND updates.id > done.last_update)",
                         -1, &s, nullptr) != SQLITE_OK)
    return Error{impl_->error("cannot read which robots are done")};
  std::map<RobotId, uint64_t> done;
  int rc = SQLITE_ROW;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    const char* text = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    const auto robot = RobotId::parse(text ? text : "");
    if (!robot) {
      sqlite3_finalize(s);
      return Error{impl_->path + ": done: unknown robot '" + (text ? text : "") + "'"};
    }
    done[*robot] = fromSql(sqlite3_column_int64(s, 1));
  }
  sqlite3_finalize(s);
  if (rc != SQLITE_DONE) return Error{impl_->error("cannot read which robots are done")};
  return done;
}

size_t Journal::size() const {
  sqlite3_stmt* s = nullptr;
  size_t n = 0;
  if (sqlite3_prepare_v2(impl_->db, "SELECT count(*) FROM updates", -1, &s, nullptr) == SQLITE_OK &&
      sqlite3_step(s) == SQLITE_ROW)
    n = static_cast<size_t>(sqlite3_column_int64(s, 0));
  sqlite3_finalize(s);
  return n;
}

std::string Journal::integrityCheck() const {
  sqlite3_stmt* s = nullptr;
  std::string result;
  if (sqlite3_prepare_v2(impl_->db, "PRAGMA integrity_check", -1, &s, nullptr) != SQLITE_OK)
    return impl_->error("cannot check");
  while (sqlite3_step(s) == SQLITE_ROW) {
    const char* line = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    result += (result.empty() ? "" : "; ") + std::string(line ? line : "");
  }
  sqlite3_finalize(s);
  return result;
}

}  // namespace hydra_multi::store
