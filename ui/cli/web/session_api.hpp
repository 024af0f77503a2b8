// The web review's API on one session (its file, a leaf's numbers, a correction) and the
// answers every endpoint gives, shared by web_app.cpp and session_api.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "http.hpp"
#include "leafdig/db/event_store.hpp"

namespace leafdig::cli::web::detail {

inline constexpr std::size_t kLongestReason = 4000;  // characters of a decision's or correction's why

// A JSON answer (text that is not UTF-8 replaced, never thrown on).
[[nodiscard]] HttpResponse jsonAnswer(int status, const nlohmann::json& body);
// An error in the API's shape: {error, what_to_do}.
[[nodiscard]] HttpResponse problem(int status, const std::string& error, const std::string& whatToDo);
// A text field of a JSON object body (none when absent or not text).
[[nodiscard]] std::optional<std::string> textField(const nlohmann::json& body, const char* key);

// GET /api/sessions/ID/export?format=…: one file as `sessions export` writes it.
[[nodiscard]] HttpResponse exportFile(db::EventStore& store, std::int64_t id, const HttpRequest& request);
// GET /api/sessions/ID/review: a leaf's metrics (with the 95 % area interval) and flags.
[[nodiscard]] HttpResponse leafReview(const db::EventStore& store, std::int64_t id);
// GET /api/sessions/ID/surveys: a plant session's plant, every dated survey of it (`plant surveys --json`).
[[nodiscard]] HttpResponse plantSurveys(const db::EventStore& store, std::int64_t id);
// POST /api/sessions/ID/correct: a dry run or a correction, as `sessions correct` makes them.
[[nodiscard]] HttpResponse correction(db::EventStore& store, std::int64_t id, const nlohmann::json& body);

}  // namespace leafdig::cli::web::detail
