// `sessions show ID [--json]`: one session as captured and reviewed (sessions_show.cpp).
#pragma once

#include "leafdig/db/event_store.hpp"
#include "sessions_options.hpp"

namespace leafdig::cli {

int runShow(const db::EventStore& store, const SessionsOptions& o);

}  // namespace leafdig::cli
