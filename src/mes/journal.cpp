#include "mes/journal.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <vector>

namespace skillcell::mes {
namespace {

// A prepared statement that finalizes itself.
class Statement {
public:
    Statement(sqlite3* db, const std::string& sql) {
        status_ =
            sqlite3_prepare_v2(db, sql.c_str(), static_cast<int>(sql.size()), &stmt_, nullptr);
    }
    ~Statement() { sqlite3_finalize(stmt_); }
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;

    [[nodiscard]] bool prepared() const { return status_ == SQLITE_OK; }
    void bind(int i, const std::string& text) {
        sqlite3_bind_text(stmt_, i, text.c_str(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
    }
    void bind(int i, std::int64_t number) { sqlite3_bind_int64(stmt_, i, number); }
    /// SQLITE_ROW, SQLITE_DONE or an error code.
    int step() { return sqlite3_step(stmt_); }
    /// Ready to be bound and stepped again (a statement used for many rows is prepared once).
    void reset() {
        sqlite3_reset(stmt_);
        sqlite3_clear_bindings(stmt_);
    }
    [[nodiscard]] std::string text(int column) const {
        const auto* p = sqlite3_column_text(stmt_, column);
        return p != nullptr ? std::string(reinterpret_cast<const char*>(p)) : std::string();
    }
    [[nodiscard]] std::int64_t number(int column) const {
        return sqlite3_column_int64(stmt_, column);
    }

private:
    sqlite3_stmt* stmt_ = nullptr;
    int status_ = SQLITE_ERROR;
};

template <class E>
std::optional<E> parseState(const std::string& text, std::initializer_list<E> all) {
    for (E e : all) {
        if (text == toString(e)) return e;
    }
    return std::nullopt;
}

constexpr const char* kSchema = R"(
CREATE TABLE IF NOT EXISTS runs (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  process TEXT NOT NULL,
  state TEXT NOT NULL,
  reason TEXT NOT NULL DEFAULT '',
  started_ms INTEGER NOT NULL,
  ended_ms INTEGER NOT NULL DEFAULT 0,
  priority INTEGER NOT NULL DEFAULT 0
);
CREATE TABLE IF NOT EXISTS steps (
  run INTEGER NOT NULL REFERENCES runs(id),
  idx INTEGER NOT NULL,
  attempt INTEGER NOT NULL,
  step TEXT NOT NULL,
  state TEXT NOT NULL,
  skill_type TEXT NOT NULL,
  component TEXT NOT NULL,
  endpoint TEXT NOT NULL,
  skill_node TEXT NOT NULL,
  transition_before INTEGER NOT NULL,
  reason TEXT NOT NULL,
  started_ms INTEGER NOT NULL,
  ended_ms INTEGER NOT NULL,
  note TEXT NOT NULL DEFAULT '',
  choice TEXT NOT NULL DEFAULT '',
  held TEXT NOT NULL DEFAULT '',
  PRIMARY KEY (run, idx, attempt)
);
)";

// A list of URIs in one column, one per line (a URI holds no line break).
std::string joinLines(const std::vector<std::string>& items) {
    std::string out;
    for (const auto& i : items) out += (out.empty() ? "" : "\n") + i;
    return out;
}

std::vector<std::string> splitLines(const std::string& text) {
    std::vector<std::string> out;
    std::size_t at = 0;
    while (at < text.size()) {
        const auto end = std::min(text.find('\n', at), text.size());
        if (end > at) out.push_back(text.substr(at, end - at));
        at = end + 1;
    }
    return out;
}

// Journals written before steps had a note, or runs a priority, get the column (the MES and a
// reader such as the dashboard may both try: the second finds it there).
bool hasColumn(sqlite3* db, const std::string& table, const std::string& column) {
    Statement s(db, "SELECT 1 FROM pragma_table_info('" + table + "') WHERE name = ?1");
    s.bind(1, column);
    return s.prepared() && s.step() == SQLITE_ROW;
}

}  // namespace

const char* toString(RunState state) {
    switch (state) {
        case RunState::Running:
            return "running";
        case RunState::Stopped:
            return "stopped";
        case RunState::Completed:
            return "completed";
        case RunState::Queued:
            return "queued";
        case RunState::Cancelled:
            return "cancelled";
    }
    return "?";
}

const char* toString(StepState state) {
    switch (state) {
        case StepState::Starting:
            return "starting";
        case StepState::Running:
            return "running";
        case StepState::Finished:
            return "finished";
        case StepState::Failed:
            return "failed";
    }
    return "?";
}

std::int64_t unixMillis() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

const StepRecord* RunRecord::lastAttempt(int index) const {
    const StepRecord* last = nullptr;
    for (const auto& s : steps) {
        if (s.index == index && (last == nullptr || s.attempt > last->attempt)) last = &s;
    }
    return last;
}

kb::Expected<std::unique_ptr<Journal>> Journal::open(const std::string& path) {
    sqlite3* db = nullptr;
    const int rc = sqlite3_open_v2(
        path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
        nullptr);
    if (rc != SQLITE_OK) {
        std::string why = db != nullptr ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
        sqlite3_close(db);
        return kb::Error{"cannot open the journal " + path + ": " + why, kb::ErrorKind::BadInput};
    }
    auto journal = std::make_unique<Journal>(Token{}, db, path);
    // Another MES on the same file waits up to 2 s for a write lock, then fails clearly.
    sqlite3_busy_timeout(db, 2000);
    for (const char* sql : {"PRAGMA journal_mode=WAL", "PRAGMA synchronous=FULL",
                            "PRAGMA foreign_keys=ON", kSchema}) {
        if (auto s = journal->exec(sql); !s) {
            return kb::Error{"cannot use " + path + " as the journal: " + s.error(),
                             kb::ErrorKind::BadInput};
        }
    }
    const struct {
        const char* table;
        const char* column;
        const char* sql;
    } added[] = {
        {"steps", "note", "ALTER TABLE steps ADD COLUMN note TEXT NOT NULL DEFAULT ''"},
        {"runs", "priority", "ALTER TABLE runs ADD COLUMN priority INTEGER NOT NULL DEFAULT 0"},
        {"steps", "choice", "ALTER TABLE steps ADD COLUMN choice TEXT NOT NULL DEFAULT ''"},
        {"steps", "held", "ALTER TABLE steps ADD COLUMN held TEXT NOT NULL DEFAULT ''"},
    };
    for (const auto& a : added) {
        if (hasColumn(db, a.table, a.column)) continue;
        auto s = journal->exec(a.sql);
        if (!s && !hasColumn(db, a.table, a.column)) {
            return kb::Error{
                "cannot add the column " + std::string(a.column) + " to " + path + ": " + s.error(),
                kb::ErrorKind::BadInput};
        }
    }
    return journal;
}

Journal::~Journal() {
    sqlite3_close(db_);
}

kb::Error Journal::error(const std::string& what) const {
    return kb::Error{"journal " + path_ + ": " + what + ": " + sqlite3_errmsg(db_)};
}

kb::Status Journal::exec(const std::string& sql) {
    char* message = nullptr;
    if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
        std::string why = message != nullptr ? message : sqlite3_errmsg(db_);
        sqlite3_free(message);
        return kb::Error{why};
    }
    return kb::Done{};
}

kb::Expected<std::int64_t> Journal::beginRun(const std::string& processIri) {
    Statement s(db_, "INSERT INTO runs (process, state, started_ms) VALUES (?1, ?2, ?3)");
    if (!s.prepared()) return error("prepare");
    s.bind(1, processIri);
    s.bind(2, std::string(toString(RunState::Running)));
    s.bind(3, unixMillis());
    if (s.step() != SQLITE_DONE) return error("cannot begin a run");
    return static_cast<std::int64_t>(sqlite3_last_insert_rowid(db_));
}

kb::Expected<std::int64_t> Journal::submitOrder(const std::string& processIri, int priority) {
    Statement s(db_,
                "INSERT INTO runs (process, state, started_ms, priority) VALUES (?1, ?2, ?3, ?4) "
                "RETURNING id");
    if (!s.prepared()) return error("prepare");
    s.bind(1, processIri);
    s.bind(2, std::string(toString(RunState::Queued)));
    s.bind(3, unixMillis());
    s.bind(4, std::int64_t{priority});
    if (s.step() != SQLITE_ROW) return error("cannot submit an order");
    const std::int64_t id = s.number(0);
    if (s.step() != SQLITE_DONE) return error("cannot submit an order");
    return id;
}

namespace {

constexpr const char* kRecordStep =
    "INSERT OR REPLACE INTO steps (run, idx, attempt, step, state, skill_type, component, "
    "endpoint, skill_node, transition_before, reason, started_ms, ended_ms, note, choice, held) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16)";

int bindAndStep(Statement& s, std::int64_t run, const StepRecord& step) {
    s.bind(1, run);
    s.bind(2, std::int64_t{step.index});
    s.bind(3, std::int64_t{step.attempt});
    s.bind(4, step.stepIri);
    s.bind(5, std::string(toString(step.state)));
    s.bind(6, step.skillTypeIri);
    s.bind(7, step.componentUri);
    s.bind(8, step.endpointUrl);
    s.bind(9, step.skillNodeId);
    s.bind(10, step.transitionTimeBefore);
    s.bind(11, step.reason);
    s.bind(12, step.startedMs);
    s.bind(13, step.endedMs);
    s.bind(14, step.note);
    s.bind(15, step.choice);
    s.bind(16, joinLines(step.held));
    const int rc = s.step();
    s.reset();
    return rc;
}

}  // namespace

kb::Status Journal::recordStep(std::int64_t run, const StepRecord& step) {
    Statement s(db_, kRecordStep);
    if (!s.prepared()) return error("prepare");
    if (bindAndStep(s, run, step) != SQLITE_DONE) {
        return error("cannot record step " + std::to_string(step.index));
    }
    return kb::Done{};
}

kb::Status Journal::recordSteps(const std::vector<std::pair<std::int64_t, StepRecord>>& steps) {
    if (steps.size() == 1) return recordStep(steps.front().first, steps.front().second);
    if (auto s = exec("BEGIN IMMEDIATE"); !s) return s;
    // One statement for the whole batch: preparing it per row cost as much as the row.
    Statement s(db_, kRecordStep);
    kb::Status result = kb::Done{};
    if (!s.prepared()) result = error("prepare");
    for (std::size_t i = 0; result && i < steps.size(); ++i) {
        if (bindAndStep(s, steps[i].first, steps[i].second) != SQLITE_DONE) {
            result = error("cannot record step " + std::to_string(steps[i].second.index));
        }
    }
    if (result) result = exec("COMMIT");
    if (!result) (void)exec("ROLLBACK");
    return result;
}

kb::Status Journal::setRunState(std::int64_t run, RunState state, const std::string& reason) {
    Statement s(db_, "UPDATE runs SET state = ?1, reason = ?2, ended_ms = ?3 WHERE id = ?4");
    if (!s.prepared()) return error("prepare");
    s.bind(1, std::string(toString(state)));
    s.bind(2, reason);
    const bool open = state == RunState::Running || state == RunState::Queued;
    s.bind(3, open ? std::int64_t{0} : unixMillis());
    s.bind(4, run);
    if (s.step() != SQLITE_DONE) return error("cannot update run " + std::to_string(run));
    if (sqlite3_changes(db_) != 1) return kb::Error{"journal: no run " + std::to_string(run)};
    return kb::Done{};
}

kb::Expected<std::vector<RunRecord>> Journal::runs(const std::string& where,
                                                   const std::string& text, std::int64_t number) {
    Statement s(db_,
                "SELECT id, process, state, reason, started_ms, ended_ms, priority FROM runs "
                "WHERE " +
                    where + " ORDER BY id");
    if (!s.prepared()) return error("prepare");
    if (!text.empty()) s.bind(1, text);
    if (number != 0) s.bind(text.empty() ? 1 : 2, number);
    std::vector<RunRecord> out;
    std::map<std::int64_t, std::size_t> byId;
    int rc = 0;
    while ((rc = s.step()) == SQLITE_ROW) {
        RunRecord r;
        r.id = s.number(0);
        r.processIri = s.text(1);
        const auto state =
            parseState(s.text(2), {RunState::Running, RunState::Stopped, RunState::Completed,
                                   RunState::Queued, RunState::Cancelled});
        if (!state)
            return kb::Error{"journal " + path_ + ": run " + std::to_string(r.id) +
                             " has the unknown state '" + s.text(2) + "'"};
        r.state = *state;
        r.reason = s.text(3);
        r.startedMs = s.number(4);
        r.endedMs = s.number(5);
        r.priority = static_cast<int>(s.number(6));
        byId[r.id] = out.size();
        out.push_back(std::move(r));
    }
    if (rc != SQLITE_DONE) return error("cannot read the runs");
    for (auto& r : out) {
        Statement q(db_,
                    "SELECT idx, attempt, step, state, skill_type, component, endpoint, "
                    "skill_node, transition_before, reason, started_ms, ended_ms, note, choice, "
                    "held FROM steps "
                    "WHERE run = ?1 ORDER BY idx, attempt");
        if (!q.prepared()) return error("prepare");
        q.bind(1, r.id);
        while ((rc = q.step()) == SQLITE_ROW) {
            StepRecord st;
            st.index = static_cast<int>(q.number(0));
            st.attempt = static_cast<int>(q.number(1));
            st.stepIri = q.text(2);
            const auto state = parseState(q.text(3), {StepState::Starting, StepState::Running,
                                                      StepState::Finished, StepState::Failed});
            if (!state)
                return kb::Error{"journal " + path_ + ": a step of run " + std::to_string(r.id) +
                                 " has the unknown state '" + q.text(3) + "'"};
            st.state = *state;
            st.skillTypeIri = q.text(4);
            st.componentUri = q.text(5);
            st.endpointUrl = q.text(6);
            st.skillNodeId = q.text(7);
            st.transitionTimeBefore = q.number(8);
            st.reason = q.text(9);
            st.startedMs = q.number(10);
            st.endedMs = q.number(11);
            st.note = q.text(12);
            st.choice = q.text(13);
            st.held = splitLines(q.text(14));
            r.steps.push_back(std::move(st));
        }
        if (rc != SQLITE_DONE) return error("cannot read the steps");
    }
    return out;
}

kb::Expected<std::optional<RunRecord>> Journal::run(std::int64_t id) {
    auto found = runs("id = ?1", {}, id);
    if (!found) return found.failure();
    if (found->empty()) return std::optional<RunRecord>();
    return std::optional<RunRecord>(std::move(found->front()));
}

kb::Expected<std::optional<RunRecord>> Journal::lastRun(const std::string& where,
                                                        const std::string& processIri) {
    auto found = runs(where, processIri, 0);
    if (!found) return found.failure();
    if (found->empty()) return std::optional<RunRecord>();
    return std::optional<RunRecord>(std::move(found->back()));
}

kb::Expected<std::optional<RunRecord>> Journal::unfinishedRun(const std::string& processIri) {
    return lastRun("process = ?1 AND state IN ('running', 'stopped')", processIri);
}

kb::Expected<std::optional<RunRecord>> Journal::latestRun(const std::string& processIri) {
    return lastRun("process = ?1", processIri);
}

kb::Expected<std::vector<RunRecord>> Journal::unfinishedRuns() {
    return runs("state NOT IN ('completed', 'cancelled')", {}, 0);
}

kb::Expected<std::vector<RunRecord>> Journal::openOrders() {
    return runs("state IN ('queued', 'running')", {}, 0);
}

kb::Expected<std::map<std::string, std::vector<std::int64_t>>> Journal::finishedDurations(
    const std::string& skillTypeIri, std::size_t perComponent) {
    Statement s(db_,
                "SELECT component, ended_ms - started_ms FROM steps WHERE skill_type = ?1 AND "
                "state = 'finished' AND ended_ms > started_ms ORDER BY ended_ms DESC LIMIT 2000");
    if (!s.prepared()) return error("prepare");
    s.bind(1, skillTypeIri);
    std::map<std::string, std::vector<std::int64_t>> out;
    int rc = 0;
    while ((rc = s.step()) == SQLITE_ROW) {
        auto& durations = out[s.text(0)];
        if (durations.size() < perComponent) durations.push_back(s.number(1));
    }
    if (rc != SQLITE_DONE) return error("cannot read the steps' durations");
    return out;
}

kb::Expected<std::vector<RunRecord>> Journal::recentRuns(std::int64_t count) {
    if (count <= 0) return std::vector<RunRecord>{};
    return runs("id > (SELECT COALESCE(MAX(id), 0) FROM runs) - ?1", {}, count);
}

}  // namespace skillcell::mes
