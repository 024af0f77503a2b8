// The lab server's schema (docs/server-schema.md), one migration per version; `leafdig
// server init` applies the missing ones, each in its own transaction. Never edit a released
// migration: add the next one.
#pragma once

#include <array>

namespace leafdig::db::detail {

// The three group roles are cluster-wide and created (if missing) before the migrations.
inline constexpr const char* kLabRoles[] = {"leafdig_technicians", "leafdig_curators", "leafdig_readers"};

inline constexpr std::array<const char*, 11> kLabMigrations = {
    // ---- version 1 --------------------------------------------------------------------------
    R"SQL(
CREATE SCHEMA leafdig;
COMMENT ON SCHEMA leafdig IS 'leafdig lab store: sessions pushed by stations, hash-chained events (docs/server-schema.md)';

CREATE TABLE leafdig.meta (key text PRIMARY KEY, value text NOT NULL);

-- A technician's login pushes for exactly one station.
CREATE TABLE leafdig.station_logins (
  login text PRIMARY KEY,
  station text NOT NULL CHECK (station ~ '^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$'));

-- A session is named by its station and the id it has there; `id` is the server's own.
CREATE TABLE leafdig.sessions (
  id bigint GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  station text NOT NULL CHECK (station ~ '^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$'),
  station_session_id bigint NOT NULL CHECK (station_session_id > 0),
  project text NOT NULL,
  plant text NOT NULL,
  leaf_position integer NOT NULL,
  leaf_type text NOT NULL DEFAULT '',
  measured_area_mm2 double precision,
  operator text NOT NULL,
  mode text NOT NULL,
  capture_order text NOT NULL,
  settings_json text NOT NULL,
  created_utc text NOT NULL,
  genesis_hash text NOT NULL,
  status text NOT NULL DEFAULT 'open',
  head_seq bigint NOT NULL DEFAULT 0,
  head_hash text NOT NULL DEFAULT '',
  pushed_by text NOT NULL DEFAULT session_user,
  first_pushed timestamptz NOT NULL DEFAULT now(),
  UNIQUE (station, station_session_id));

-- Append-only: every event of every session, as its station wrote it (or a curator here).
CREATE TABLE leafdig.events (
  session_id bigint NOT NULL REFERENCES leafdig.sessions (id),
  station text NOT NULL,
  seq bigint NOT NULL CHECK (seq > 0),
  utc text NOT NULL,
  mono_ns bigint NOT NULL,
  kind text NOT NULL,
  payload_json text NOT NULL,
  raw text NOT NULL,
  prev_hash text NOT NULL,
  hash text NOT NULL,
  written_by text NOT NULL DEFAULT session_user,
  received timestamptz NOT NULL DEFAULT clock_timestamp(),
  PRIMARY KEY (session_id, seq));
CREATE INDEX events_by_station ON leafdig.events (station);

CREATE TABLE leafdig.exports (
  id bigint GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  session_id bigint NOT NULL REFERENCES leafdig.sessions (id),
  path text NOT NULL,
  format text NOT NULL,
  utc text NOT NULL,
  written_by text NOT NULL DEFAULT session_user);

-- Who may do what. `who` is the login (session_user in the triggers, current_user in the
-- policies). The schema's owner (who ran `leafdig server init`) and superusers are admins.
CREATE FUNCTION leafdig.is_admin(who name) RETURNS boolean LANGUAGE sql STABLE
  SET search_path = pg_catalog AS $$
  SELECT coalesce((SELECT rolsuper FROM pg_roles WHERE rolname = who), false)
      OR pg_has_role(who, (SELECT nspowner FROM pg_namespace WHERE nspname = 'leafdig'), 'MEMBER') $$;
CREATE FUNCTION leafdig.login_station(who name) RETURNS text LANGUAGE sql STABLE
  SET search_path = pg_catalog AS $$
  SELECT station FROM leafdig.station_logins WHERE login = who $$;
-- Approving, rejecting and correcting are a curator's; everything else is capture.
CREATE FUNCTION leafdig.is_review_event(kind text, payload text) RETURNS boolean LANGUAGE sql IMMUTABLE
  SET search_path = pg_catalog AS $$
  SELECT CASE WHEN kind = 'corrected' THEN true
              WHEN kind = 'status' THEN coalesce((payload::jsonb ->> 'status') IN ('approved', 'rejected'), false)
              ELSE false END $$;
CREATE FUNCTION leafdig.chain_hash(prev text, station_session bigint, seq bigint, utc text, mono bigint, kind text,
                                   payload text, raw text) RETURNS text LANGUAGE sql IMMUTABLE
  SET search_path = pg_catalog AS $$
  SELECT encode(sha256(convert_to(prev || E'\n' || station_session || E'\n' || seq || E'\n' || utc || E'\n' ||
                                  mono || E'\n' || kind || E'\n' || octet_length(payload) || ':' || payload ||
                                  E'\n' || octet_length(raw) || ':' || raw, 'UTF8')), 'hex') $$;

-- A new session: pushed by its own station's technician (or an admin), its genesis hash
-- recomputed; it starts empty and open whatever the client says.
CREATE FUNCTION leafdig.session_arrives() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog AS $$
DECLARE
  bound text := leafdig.login_station(session_user);
BEGIN
  IF NOT leafdig.is_admin(session_user) THEN
    IF NOT pg_has_role(session_user, 'leafdig_technicians', 'MEMBER') THEN
      RAISE EXCEPTION 'the login % may not push sessions: only a station''s technician pushes them', session_user
        USING ERRCODE = '42501', HINT = 'push with the technician login of station ' || NEW.station || ' (leafdig server add-user --role technician)';
    END IF;
    IF bound IS DISTINCT FROM NEW.station THEN
      RAISE EXCEPTION 'the login % pushes for station %, not for station % (session %:%)', session_user,
        coalesce(bound, '(none)'), NEW.station, NEW.station, NEW.station_session_id
        USING ERRCODE = '42501', HINT = 'push a station''s file with that station''s login';
    END IF;
  END IF;
  IF NEW.genesis_hash IS DISTINCT FROM encode(sha256(convert_to('leafdig session ' || NEW.station_session_id || ' ' ||
                                          NEW.created_utc || ' ' || NEW.settings_json, 'UTF8')), 'hex') THEN
    RAISE EXCEPTION 'session %:% does not hash to its genesis hash (its creation time or settings were changed)',
      NEW.station, NEW.station_session_id USING ERRCODE = 'LD002';
  END IF;
  NEW.status := 'open';
  NEW.head_seq := 0;
  NEW.head_hash := NEW.genesis_hash;
  NEW.pushed_by := session_user;
  NEW.first_pushed := now();
  RETURN NEW;
END $$;
CREATE TRIGGER session_arrives BEFORE INSERT ON leafdig.sessions
  FOR EACH ROW EXECUTE FUNCTION leafdig.session_arrives();

-- Every event: who may add it, then the chain — the next seq, after the session's head,
-- hashing to what it says — then the session's head (and status) move with it, in the same
-- statement. Rows of one INSERT are checked one after the other, in order.
CREATE FUNCTION leafdig.event_arrives() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog AS $$
DECLARE
  s record;
  review boolean := leafdig.is_review_event(NEW.kind, NEW.payload_json);
  bound text := leafdig.login_station(session_user);
BEGIN
  SELECT id, station, station_session_id, head_seq, head_hash INTO s
    FROM leafdig.sessions WHERE id = NEW.session_id FOR UPDATE;
  IF NOT FOUND THEN
    RAISE EXCEPTION 'there is no session % on the server', NEW.session_id USING ERRCODE = 'LD003';
  END IF;
  IF NEW.station IS DISTINCT FROM s.station THEN
    RAISE EXCEPTION 'event % names station % but session %:% is station %''s', NEW.seq, NEW.station, s.station,
      s.station_session_id, s.station USING ERRCODE = '42501';
  END IF;
  IF NOT leafdig.is_admin(session_user) THEN
    IF review THEN
      IF NOT pg_has_role(session_user, 'leafdig_curators', 'MEMBER') THEN
        RAISE EXCEPTION 'the login % may not approve, reject or correct sessions (session %:%, event %): only curators review',
          session_user, s.station, s.station_session_id, NEW.seq
          USING ERRCODE = '42501', HINT = 'a curator reviews on the server (leafdig sessions approve --db postgresql://…) and the station takes the decision in with leafdig sync pull';
      END IF;
    ELSIF NOT pg_has_role(session_user, 'leafdig_technicians', 'MEMBER') THEN
      RAISE EXCEPTION 'the login % may not add capture events (session %:%, event %): only the station''s technician pushes them',
        session_user, s.station, s.station_session_id, NEW.seq USING ERRCODE = '42501';
    ELSIF bound IS DISTINCT FROM s.station THEN
      RAISE EXCEPTION 'the login % pushes for station %, not for station % (session %:%, event %)', session_user,
        coalesce(bound, '(none)'), s.station, s.station, s.station_session_id, NEW.seq
        USING ERRCODE = '42501', HINT = 'push a station''s file with that station''s login';
    END IF;
  END IF;
  IF NEW.seq <> s.head_seq + 1 THEN
    RAISE EXCEPTION 'session %:% event % does not follow: the server holds events 1 to %', s.station,
      s.station_session_id, NEW.seq, s.head_seq USING ERRCODE = 'LD001';
  END IF;
  IF NEW.prev_hash IS DISTINCT FROM s.head_hash THEN
    RAISE EXCEPTION 'session %:% event % does not follow the server''s event % (another previous hash): the station''s copy and the server''s differ',
      s.station, s.station_session_id, NEW.seq, s.head_seq USING ERRCODE = 'LD001';
  END IF;
  IF NEW.hash IS DISTINCT FROM leafdig.chain_hash(NEW.prev_hash, s.station_session_id, NEW.seq, NEW.utc,
                                                  NEW.mono_ns, NEW.kind, NEW.payload_json, NEW.raw) THEN
    RAISE EXCEPTION 'session %:% event % does not hash to its hash: it was changed after it was written',
      s.station, s.station_session_id, NEW.seq USING ERRCODE = 'LD002';
  END IF;
  UPDATE leafdig.sessions
     SET head_seq = NEW.seq, head_hash = NEW.hash,
         status = CASE WHEN NEW.kind = 'status' THEN coalesce(NEW.payload_json::jsonb ->> 'status', status) ELSE status END
   WHERE id = s.id;
  NEW.written_by := session_user;
  NEW.received := clock_timestamp();
  RETURN NEW;
END $$;
CREATE TRIGGER event_arrives BEFORE INSERT ON leafdig.events
  FOR EACH ROW EXECUTE FUNCTION leafdig.event_arrives();

CREATE FUNCTION leafdig.append_only() RETURNS trigger LANGUAGE plpgsql
  SET search_path = pg_catalog AS $$
BEGIN
  RAISE EXCEPTION 'events are append-only: % refused (a correction is a new event)', TG_OP USING ERRCODE = '42501';
END $$;
CREATE TRIGGER events_append_only BEFORE UPDATE OR DELETE ON leafdig.events
  FOR EACH ROW EXECUTE FUNCTION leafdig.append_only();
CREATE TRIGGER events_no_truncate BEFORE TRUNCATE ON leafdig.events
  FOR EACH STATEMENT EXECUTE FUNCTION leafdig.append_only();

-- Grants: read for all three groups, pushing for technicians, review events for curators.
-- Nobody but the schema's owner updates or deletes anything.
REVOKE ALL ON ALL TABLES IN SCHEMA leafdig FROM PUBLIC;
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT USAGE ON SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
GRANT SELECT ON leafdig.meta, leafdig.station_logins, leafdig.sessions, leafdig.events, leafdig.exports
  TO leafdig_technicians, leafdig_curators, leafdig_readers;
GRANT INSERT ON leafdig.sessions TO leafdig_technicians;
GRANT INSERT ON leafdig.events TO leafdig_technicians, leafdig_curators;
GRANT INSERT ON leafdig.exports TO leafdig_technicians, leafdig_curators;

-- Row-level security: a technician sees and pushes its own station's rows only; curators
-- and readers see everything; only review events from curators. (The triggers above say
-- the same with clearer words; these hold even if a trigger were dropped.)
ALTER TABLE leafdig.sessions ENABLE ROW LEVEL SECURITY;
CREATE POLICY read_all ON leafdig.sessions FOR SELECT TO leafdig_curators, leafdig_readers USING (true);
CREATE POLICY read_own ON leafdig.sessions FOR SELECT TO leafdig_technicians
  USING (station = leafdig.login_station(current_user));
CREATE POLICY push_own ON leafdig.sessions FOR INSERT TO leafdig_technicians
  WITH CHECK (station = leafdig.login_station(current_user));
ALTER TABLE leafdig.events ENABLE ROW LEVEL SECURITY;
CREATE POLICY read_all ON leafdig.events FOR SELECT TO leafdig_curators, leafdig_readers USING (true);
CREATE POLICY read_own ON leafdig.events FOR SELECT TO leafdig_technicians
  USING (station = leafdig.login_station(current_user));
CREATE POLICY push_own ON leafdig.events FOR INSERT TO leafdig_technicians
  WITH CHECK (station = leafdig.login_station(current_user) AND NOT leafdig.is_review_event(kind, payload_json));
CREATE POLICY review_any ON leafdig.events FOR INSERT TO leafdig_curators
  WITH CHECK (leafdig.is_review_event(kind, payload_json));
ALTER TABLE leafdig.exports ENABLE ROW LEVEL SECURITY;
CREATE POLICY read_visible ON leafdig.exports FOR SELECT TO leafdig_technicians, leafdig_curators, leafdig_readers
  USING (EXISTS (SELECT 1 FROM leafdig.sessions s WHERE s.id = session_id));
CREATE POLICY record_visible ON leafdig.exports FOR INSERT TO leafdig_technicians, leafdig_curators
  WITH CHECK (EXISTS (SELECT 1 FROM leafdig.sessions s WHERE s.id = session_id));
)SQL",

    // ---- version 2: the rules of docs/lab.md, "Roles", held by the server --------------------
    // Found by an attack on a throw-away server (issue 25): a technician could overturn a
    // curator's decision, fake one with "approved ", undo a correction, shadow pg_roles with a
    // temporary table, claim session ids, learn other stations' sessions from error texts and
    // sign exports as another login. Every function reads catalogs by schema-qualified names
    // with the temporary schema searched last; every event is checked against a closed set of
    // kinds, statuses and payloads and against the session's state; ids and signatures are
    // the server's.
    R"SQL(
CREATE OR REPLACE FUNCTION leafdig.is_admin(who name) RETURNS boolean LANGUAGE sql STABLE
  SET search_path = pg_catalog, pg_temp AS $$
  SELECT coalesce((SELECT r.rolsuper FROM pg_catalog.pg_roles r WHERE r.rolname = who), false)
      OR pg_catalog.pg_has_role(who, (SELECT n.nspowner FROM pg_catalog.pg_namespace n WHERE n.nspname = 'leafdig'),
                                'MEMBER') $$;
CREATE OR REPLACE FUNCTION leafdig.login_station(who name) RETURNS text LANGUAGE sql STABLE
  SET search_path = pg_catalog, pg_temp AS $$
  SELECT l.station FROM leafdig.station_logins l WHERE l.login = who $$;
CREATE OR REPLACE FUNCTION leafdig.is_review_event(kind text, payload text) RETURNS boolean LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  IF kind = 'corrected' THEN RETURN true; END IF;
  IF kind <> 'status' THEN RETURN false; END IF;
  RETURN coalesce((payload::jsonb ->> 'status') IN ('approved', 'rejected'), false);
EXCEPTION WHEN others THEN
  RETURN false;  -- not JSON: not a review event (event_arrives refuses it by name)
END $$;
CREATE OR REPLACE FUNCTION leafdig.chain_hash(prev text, station_session bigint, seq bigint, utc text, mono bigint,
                                              kind text, payload text, raw text) RETURNS text LANGUAGE sql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
  SELECT pg_catalog.encode(pg_catalog.sha256(pg_catalog.convert_to(
           prev || E'\n' || station_session || E'\n' || seq || E'\n' || utc || E'\n' || mono || E'\n' || kind ||
           E'\n' || pg_catalog.octet_length(payload) || ':' || payload || E'\n' || pg_catalog.octet_length(raw) ||
           ':' || raw, 'UTF8')), 'hex') $$;

-- The closed sets of docs/schema.md, "Event kinds".
CREATE FUNCTION leafdig.is_item(item jsonb) RETURNS boolean LANGUAGE sql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
  SELECT coalesce(pg_catalog.jsonb_typeof(item) = 'object'
     AND coalesce(item ->> 'what', '') IN ('board', 'tip', 'marker', 'midrib_thickness', 'vein_origin_thickness',
                                           'edge_thickness', 'point_thickness')
     AND coalesce(pg_catalog.jsonb_typeof(item -> 'row'), 'null') IN ('null', 'number')
     AND coalesce(pg_catalog.jsonb_typeof(item -> 'col'), 'null') IN ('null', 'number')
     AND CASE WHEN item ->> 'what' IN ('board', 'tip', 'marker')
              THEN pg_catalog.jsonb_typeof(item -> 'position_mm') = 'array'
                   AND pg_catalog.jsonb_array_length(item -> 'position_mm') = 3
                   AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 0) = 'number'
                   AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 1) = 'number'
                   AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 2) = 'number'
              ELSE pg_catalog.jsonb_typeof(item -> 'value_mm') = 'number' AND (item ->> 'value_mm')::numeric > 0
         END, false) $$;

-- What is wrong with an event's kind and payload, or NULL. `named_kind` is the kind of the
-- event its payload's "seq" names (NULL when there is none).
CREATE FUNCTION leafdig.payload_problem(kind text, payload text, seq bigint, named_kind text) RETURNS text
  LANGUAGE plpgsql IMMUTABLE SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  p jsonb;
BEGIN
  IF kind NOT IN ('accepted', 'rejected', 'undone', 'retake', 'retake_cancelled', 'rows_ended', 'rows_reopened',
                  'corrected', 'paused', 'resumed', 'device', 'ignored_reading', 'status') THEN
    RETURN 'its kind is not one leafdig writes';
  END IF;
  BEGIN
    p := payload::jsonb;
  EXCEPTION WHEN others THEN
    RETURN 'its payload is not JSON';
  END;
  IF pg_catalog.jsonb_typeof(p) <> 'object' THEN RETURN 'its payload is not a JSON object'; END IF;
  IF kind = 'status' THEN
    IF coalesce(pg_catalog.jsonb_typeof(p -> 'status'), '') <> 'string'
       OR p ->> 'status' NOT IN ('open', 'complete', 'approved', 'rejected', 'abandoned') THEN
      RETURN 'its status is not one of open, complete, approved, rejected, abandoned';
    END IF;
  ELSIF kind IN ('accepted', 'retake_cancelled') THEN
    IF NOT leafdig.is_item(p) THEN RETURN 'its payload is not an item (what, row, col, position_mm or value_mm)'; END IF;
  ELSIF kind IN ('undone', 'retake', 'corrected') THEN
    IF coalesce(pg_catalog.jsonb_typeof(p -> 'seq'), '') <> 'number' OR (p ->> 'seq') !~ '^[0-9]+$'
       OR (p ->> 'seq')::numeric >= seq THEN
      RETURN 'its payload does not name an earlier event (seq)';
    END IF;
    IF kind = 'corrected' THEN
      IF named_kind IS NULL OR named_kind NOT IN ('accepted', 'retake_cancelled', 'corrected') THEN
        RETURN 'it corrects event ' || (p ->> 'seq') || ', which put no item in';
      END IF;
      IF NOT leafdig.is_item(p -> 'corrected') OR coalesce(pg_catalog.jsonb_typeof(p -> 'reason'), '') <> 'string'
         OR coalesce(pg_catalog.jsonb_typeof(p -> 'who'), '') <> 'string' THEN
        RETURN 'its payload lacks the corrected item, the reason or who corrected';
      END IF;
    ELSIF named_kind IS NULL OR named_kind NOT IN ('accepted', 'retake_cancelled') THEN
      -- a curator's correction is never undone by capture: the curator corrects again
      RETURN 'it takes back event ' || (p ->> 'seq') || ', which is not a captured item';
    END IF;
  END IF;
  RETURN NULL;
END $$;

CREATE OR REPLACE FUNCTION leafdig.session_arrives() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  bound text := leafdig.login_station(session_user);
BEGIN
  IF NOT leafdig.is_admin(session_user) THEN
    IF NOT pg_catalog.pg_has_role(session_user, 'leafdig_technicians', 'MEMBER') THEN
      RAISE EXCEPTION 'the login % may not push sessions: only a station''s technician pushes them', session_user
        USING ERRCODE = '42501', HINT = 'push with the technician login of the station (leafdig server add-user --role technician)';
    END IF;
    IF bound IS DISTINCT FROM NEW.station THEN
      RAISE EXCEPTION 'the login % pushes for station %, not for station % (session %:%)', session_user,
        coalesce(bound, '(none)'), NEW.station, NEW.station, NEW.station_session_id
        USING ERRCODE = '42501', HINT = 'push a station''s file with that station''s login';
    END IF;
  END IF;
  IF NEW.genesis_hash IS DISTINCT FROM pg_catalog.encode(pg_catalog.sha256(pg_catalog.convert_to(
       'leafdig session ' || NEW.station_session_id || ' ' || NEW.created_utc || ' ' || NEW.settings_json, 'UTF8')),
       'hex') THEN
    RAISE EXCEPTION 'session %:% does not hash to its genesis hash (its creation time or settings were changed)',
      NEW.station, NEW.station_session_id USING ERRCODE = 'LD002';
  END IF;
  NEW.status := 'open';
  NEW.head_seq := 0;
  NEW.head_hash := NEW.genesis_hash;
  NEW.pushed_by := session_user;
  NEW.first_pushed := pg_catalog.now();
  RETURN NEW;
END $$;

-- Every event: the session as the login may see it (another station's session is "no
-- session", whatever it holds), who may add what, in which state of the session, a kind and
-- payload leafdig writes, then the chain; the session's head (and status) move with it.
--   technician: capture events of its station, while the session is open; of statuses only
--               complete or abandoned (the capture's end);
--   curator:    corrections and decisions (approved, rejected) on a complete session;
--   after a decision (approved or rejected) nothing more, from anyone.
CREATE OR REPLACE FUNCTION leafdig.event_arrives() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  s record;
  admin boolean := leafdig.is_admin(session_user);
  curator boolean := pg_catalog.pg_has_role(session_user, 'leafdig_curators', 'MEMBER');
  technician boolean := pg_catalog.pg_has_role(session_user, 'leafdig_technicians', 'MEMBER');
  bound text := leafdig.login_station(session_user);
  review boolean := leafdig.is_review_event(NEW.kind, NEW.payload_json);
  named_kind text;
  problem text;
  new_status text;
BEGIN
  SELECT x.id, x.station, x.station_session_id, x.head_seq, x.head_hash, x.status INTO s
    FROM leafdig.sessions x WHERE x.id = NEW.session_id FOR UPDATE;
  -- What a login may not see does not exist for it: the same words for both.
  IF NOT FOUND OR NOT (admin OR curator OR (technician AND bound IS NOT DISTINCT FROM s.station)) THEN
    IF NOT (admin OR curator OR technician) THEN
      RAISE EXCEPTION 'the login % may not add events: it only reads', session_user USING ERRCODE = '42501';
    END IF;
    RAISE EXCEPTION 'there is no session % on the server that the login % may add to', NEW.session_id, session_user
      USING ERRCODE = 'LD003';
  END IF;
  IF NEW.station IS DISTINCT FROM s.station THEN
    RAISE EXCEPTION 'event % names station % but session %:% is station %''s', NEW.seq, NEW.station, s.station,
      s.station_session_id, s.station USING ERRCODE = '42501';
  END IF;
  IF NOT admin THEN
    IF review THEN
      IF NOT curator THEN
        RAISE EXCEPTION 'the login % may not approve, reject or correct sessions (session %:%, event %): only curators review',
          session_user, s.station, s.station_session_id, NEW.seq
          USING ERRCODE = '42501', HINT = 'a curator reviews on the server (leafdig sessions approve --db postgresql://…) and the station takes the decision in with leafdig sync pull';
      END IF;
    ELSIF NOT technician OR bound IS DISTINCT FROM s.station THEN
      RAISE EXCEPTION 'the login % may not add capture events (session %:%, event %): only the station''s technician pushes them',
        session_user, s.station, s.station_session_id, NEW.seq USING ERRCODE = '42501';
    END IF;
  END IF;
  IF s.status IN ('approved', 'rejected') THEN
    RAISE EXCEPTION 'session %:% was % by a curator: the decision is final and nothing follows it (event % refused)',
      s.station, s.station_session_id, s.status, NEW.seq
      USING ERRCODE = '42501', HINT = 'take the decision in with leafdig sync pull';
  END IF;
  IF review AND s.status <> 'complete' THEN
    RAISE EXCEPTION 'session %:% is %: only a complete session is corrected, approved or rejected (event %)',
      s.station, s.station_session_id, s.status, NEW.seq USING ERRCODE = '42501';
  END IF;
  IF NOT review AND s.status <> 'open' THEN
    RAISE EXCEPTION 'session %:% is %: its capture is over and only a curator adds to it (event % refused)',
      s.station, s.station_session_id, s.status, NEW.seq USING ERRCODE = '42501';
  END IF;
  IF NEW.kind IN ('undone', 'retake', 'corrected') THEN
    BEGIN
      SELECT e.kind INTO named_kind FROM leafdig.events e
       WHERE e.session_id = NEW.session_id AND e.seq = (NEW.payload_json::jsonb ->> 'seq')::bigint;
    EXCEPTION WHEN others THEN
      named_kind := NULL;  -- payload_problem names what is wrong
    END;
  END IF;
  problem := leafdig.payload_problem(NEW.kind, NEW.payload_json, NEW.seq, named_kind);
  IF problem IS NULL AND NEW.kind = 'status' THEN
    new_status := NEW.payload_json::jsonb ->> 'status';
    IF NOT review AND new_status NOT IN ('complete', 'abandoned') THEN
      problem := 'a capture ends as complete or abandoned, not ' || new_status;
    END IF;
  END IF;
  IF problem IS NOT NULL THEN
    RAISE EXCEPTION 'session %:% event % (%) refused: %', s.station, s.station_session_id, NEW.seq,
      pg_catalog.left(NEW.kind, 40), problem
      USING ERRCODE = '22023', HINT = 'only what leafdig writes is taken (docs/schema.md, "Event kinds")';
  END IF;
  IF NEW.seq <> s.head_seq + 1 THEN
    RAISE EXCEPTION 'session %:% event % does not follow: the server holds events 1 to %', s.station,
      s.station_session_id, NEW.seq, s.head_seq USING ERRCODE = 'LD001';
  END IF;
  IF NEW.prev_hash IS DISTINCT FROM s.head_hash THEN
    RAISE EXCEPTION 'session %:% event % does not follow the server''s event % (another previous hash): the station''s copy and the server''s differ',
      s.station, s.station_session_id, NEW.seq, s.head_seq USING ERRCODE = 'LD001';
  END IF;
  IF NEW.hash IS DISTINCT FROM leafdig.chain_hash(NEW.prev_hash, s.station_session_id, NEW.seq, NEW.utc,
                                                  NEW.mono_ns, NEW.kind, NEW.payload_json, NEW.raw) THEN
    RAISE EXCEPTION 'session %:% event % does not hash to its hash: it was changed after it was written',
      s.station, s.station_session_id, NEW.seq USING ERRCODE = 'LD002';
  END IF;
  UPDATE leafdig.sessions x SET head_seq = NEW.seq, head_hash = NEW.hash, status = coalesce(new_status, x.status)
   WHERE x.id = s.id;
  NEW.written_by := session_user;
  NEW.received := pg_catalog.clock_timestamp();
  RETURN NEW;
END $$;

CREATE OR REPLACE FUNCTION leafdig.append_only() RETURNS trigger LANGUAGE plpgsql
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RAISE EXCEPTION 'events are append-only: % refused (a correction is a new event)', TG_OP USING ERRCODE = '42501';
END $$;

-- An export is signed by the login that records it, at the server's id.
CREATE FUNCTION leafdig.export_arrives() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  NEW.written_by := session_user;
  RETURN NEW;
END $$;
CREATE TRIGGER export_arrives BEFORE INSERT ON leafdig.exports
  FOR EACH ROW EXECUTE FUNCTION leafdig.export_arrives();

-- A session's status is one of five words.
ALTER TABLE leafdig.sessions ADD CONSTRAINT sessions_status_known
  CHECK (status IN ('open', 'complete', 'approved', 'rejected', 'abandoned')) NOT VALID;

-- Ids, signatures and arrival times are the server's: logins insert only the columns they
-- bring (an INSERT naming id, written_by, pushed_by, … is refused, OVERRIDING SYSTEM VALUE too).
REVOKE INSERT ON leafdig.sessions, leafdig.events, leafdig.exports
  FROM leafdig_technicians, leafdig_curators, leafdig_readers;
GRANT INSERT (station, station_session_id, project, plant, leaf_position, leaf_type, measured_area_mm2, operator,
              mode, capture_order, settings_json, created_utc, genesis_hash) ON leafdig.sessions TO leafdig_technicians;
GRANT INSERT (session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) ON leafdig.events
  TO leafdig_technicians, leafdig_curators;
GRANT INSERT (session_id, path, format, utc) ON leafdig.exports TO leafdig_technicians, leafdig_curators;
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
)SQL",
    // ---- version 3: plant sessions (docs/server-schema.md, "Plant sessions") -----------------
    R"SQL(
-- A session captures one leaf or a whole plant. A plant session has no leaf (position 0, no
-- type, no measured area) and says so in its settings ({"kind": "plant", …}, which the genesis
-- hash covers), so a push cannot relabel a session of one kind as the other.
ALTER TABLE leafdig.sessions ADD COLUMN kind text NOT NULL DEFAULT 'leaf';
ALTER TABLE leafdig.sessions ADD CONSTRAINT sessions_kind_known CHECK (
  kind IN ('leaf', 'plant')
  AND (kind = 'leaf' OR (leaf_position = 0 AND leaf_type = '' AND measured_area_mm2 IS NULL)));

CREATE FUNCTION leafdig.settings_kind(settings text) RETURNS text LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN coalesce(settings::jsonb ->> 'kind', 'leaf');
EXCEPTION WHEN others THEN
  RETURN 'leaf';  -- not JSON, or not an object: no plant's settings
END $$;

CREATE FUNCTION leafdig.session_kind_holds() RETURNS trigger LANGUAGE plpgsql
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  IF NEW.kind IS DISTINCT FROM leafdig.settings_kind(NEW.settings_json) THEN
    RAISE EXCEPTION 'session %:% is pushed as a % session but its settings are a %''s', NEW.station,
      NEW.station_session_id, NEW.kind, leafdig.settings_kind(NEW.settings_json)
      USING ERRCODE = '22023', HINT = 'a session''s kind is what its settings say (docs/server-schema.md, "Plant sessions")';
  END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER session_kind_holds BEFORE INSERT ON leafdig.sessions
  FOR EACH ROW EXECUTE FUNCTION leafdig.session_kind_holds();

-- A plant session's items: the plant's own words, or a full leaf's item with its node
-- ("node3.marker"), each as the leaf's item rules say.
CREATE FUNCTION leafdig.is_plant_item(item jsonb) RETURNS boolean LANGUAGE sql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
  SELECT coalesce(CASE
    WHEN pg_catalog.jsonb_typeof(item) <> 'object' THEN false
    WHEN coalesce(item ->> 'what', '') ~ '^node[1-9][0-9]{0,3}\.[a-z_]+$' THEN
      pg_catalog.split_part(item ->> 'what', '.', 2) <> 'board'
      AND leafdig.is_item(item || pg_catalog.jsonb_build_object('what', pg_catalog.split_part(item ->> 'what', '.', 2)))
    ELSE coalesce(item ->> 'what', '') IN ('landmark', 'collar', 'point', 'quick_point', 'collar_diameter', 'reading')
      AND coalesce(pg_catalog.jsonb_typeof(item -> 'row'), 'null') IN ('null', 'number')
      AND coalesce(pg_catalog.jsonb_typeof(item -> 'col'), 'null') IN ('null', 'number')
      AND CASE WHEN item ->> 'what' IN ('landmark', 'collar', 'point', 'quick_point')
               THEN pg_catalog.jsonb_typeof(item -> 'position_mm') = 'array'
                    AND pg_catalog.jsonb_array_length(item -> 'position_mm') = 3
                    AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 0) = 'number'
                    AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 1) = 'number'
                    AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 2) = 'number'
               ELSE pg_catalog.jsonb_typeof(item -> 'value_mm') = 'number' AND (item ->> 'value_mm')::numeric > 0
          END
  END, false) $$;

-- A node number in a plant event's payload.
CREATE FUNCTION leafdig.names_node(p jsonb) RETURNS boolean LANGUAGE sql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
  SELECT coalesce(pg_catalog.jsonb_typeof(p -> 'node') = 'number' AND (p ->> 'node') ~ '^[1-9][0-9]{0,3}$', false) $$;

-- What is wrong with an event's kind and payload in a session of `session_kind`, or NULL.
CREATE FUNCTION leafdig.payload_problem(kind text, payload text, seq bigint, named_kind text, session_kind text)
  RETURNS text LANGUAGE plpgsql IMMUTABLE SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  p jsonb;
BEGIN
  IF session_kind = 'leaf' THEN
    IF kind IN ('landmarks_ended', 'landmarks_reopened', 'plant_ended', 'plant_reopened', 'leaf_chosen',
                'choice_undone') THEN
      RETURN 'it is a plant session''s event and this session captures one leaf';
    END IF;
    RETURN leafdig.payload_problem(kind, payload, seq, named_kind);
  END IF;
  IF kind NOT IN ('accepted', 'rejected', 'undone', 'rows_ended', 'rows_reopened', 'corrected', 'paused', 'resumed',
                  'device', 'ignored_reading', 'status', 'landmarks_ended', 'landmarks_reopened', 'plant_ended',
                  'plant_reopened', 'leaf_chosen', 'choice_undone') THEN
    RETURN 'its kind is not one leafdig writes for a plant session';
  END IF;
  IF kind = 'status' THEN
    RETURN leafdig.payload_problem(kind, payload, seq, named_kind);  -- the same five words
  END IF;
  BEGIN
    p := payload::jsonb;
  EXCEPTION WHEN others THEN
    RETURN 'its payload is not JSON';
  END;
  IF pg_catalog.jsonb_typeof(p) <> 'object' THEN RETURN 'its payload is not a JSON object'; END IF;
  IF kind = 'accepted' THEN
    IF NOT leafdig.is_plant_item(p) THEN
      RETURN 'its payload is not a plant''s item (landmark, collar, point, quick_point, collar_diameter, reading, or nodeK. before a leaf''s item)';
    END IF;
  ELSIF kind IN ('undone', 'corrected') THEN
    IF coalesce(pg_catalog.jsonb_typeof(p -> 'seq'), '') <> 'number' OR (p ->> 'seq') !~ '^[0-9]+$'
       OR (p ->> 'seq')::numeric >= seq THEN
      RETURN 'its payload does not name an earlier event (seq)';
    END IF;
    IF kind = 'corrected' THEN
      IF named_kind IS NULL OR named_kind NOT IN ('accepted', 'corrected') THEN
        RETURN 'it corrects event ' || (p ->> 'seq') || ', which put no item in';
      END IF;
      IF NOT leafdig.is_plant_item(p -> 'corrected') OR coalesce(pg_catalog.jsonb_typeof(p -> 'reason'), '') <> 'string'
         OR coalesce(pg_catalog.jsonb_typeof(p -> 'who'), '') <> 'string' THEN
        RETURN 'its payload lacks the corrected item, the reason or who corrected';
      END IF;
    ELSIF named_kind IS NULL OR named_kind <> 'accepted' THEN
      RETURN 'it takes back event ' || (p ->> 'seq') || ', which is not a captured item';
    END IF;
  ELSIF kind IN ('rows_ended', 'rows_reopened') THEN
    IF NOT leafdig.names_node(p) THEN RETURN 'its payload does not name the node whose leaf it is (node)'; END IF;
  ELSIF kind IN ('leaf_chosen', 'choice_undone') THEN
    IF NOT (leafdig.names_node(p) AND coalesce(p ->> 'kind', '') IN ('full', 'quick', 'none')
            AND coalesce(p ->> 'state', '') IN ('alive', 'dead', 'broken', 'yellow', 'pruned')
            AND (NOT p ? 'type' OR (pg_catalog.jsonb_typeof(p -> 'type') = 'string'
                                    AND pg_catalog.char_length(p ->> 'type') <= 64))) THEN
      RETURN 'its payload is not a leaf''s choice (node; kind full, quick or none; state alive, dead, broken, yellow or pruned; a type of at most 64 characters)';
    END IF;
  END IF;
  RETURN NULL;
END $$;
)SQL"
    R"SQL(
-- Every event, as in version 2, with the rules of its session's kind.
CREATE OR REPLACE FUNCTION leafdig.event_arrives() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  s record;
  admin boolean := leafdig.is_admin(session_user);
  curator boolean := pg_catalog.pg_has_role(session_user, 'leafdig_curators', 'MEMBER');
  technician boolean := pg_catalog.pg_has_role(session_user, 'leafdig_technicians', 'MEMBER');
  bound text := leafdig.login_station(session_user);
  review boolean := leafdig.is_review_event(NEW.kind, NEW.payload_json);
  named_kind text;
  problem text;
  new_status text;
BEGIN
  SELECT x.id, x.station, x.station_session_id, x.head_seq, x.head_hash, x.status, x.kind INTO s
    FROM leafdig.sessions x WHERE x.id = NEW.session_id FOR UPDATE;
  -- What a login may not see does not exist for it: the same words for both.
  IF NOT FOUND OR NOT (admin OR curator OR (technician AND bound IS NOT DISTINCT FROM s.station)) THEN
    IF NOT (admin OR curator OR technician) THEN
      RAISE EXCEPTION 'the login % may not add events: it only reads', session_user USING ERRCODE = '42501';
    END IF;
    RAISE EXCEPTION 'there is no session % on the server that the login % may add to', NEW.session_id, session_user
      USING ERRCODE = 'LD003';
  END IF;
  IF NEW.station IS DISTINCT FROM s.station THEN
    RAISE EXCEPTION 'event % names station % but session %:% is station %''s', NEW.seq, NEW.station, s.station,
      s.station_session_id, s.station USING ERRCODE = '42501';
  END IF;
  IF NOT admin THEN
    IF review THEN
      IF NOT curator THEN
        RAISE EXCEPTION 'the login % may not approve, reject or correct sessions (session %:%, event %): only curators review',
          session_user, s.station, s.station_session_id, NEW.seq
          USING ERRCODE = '42501', HINT = 'a curator reviews on the server (leafdig sessions approve --db postgresql://…) and the station takes the decision in with leafdig sync pull';
      END IF;
    ELSIF NOT technician OR bound IS DISTINCT FROM s.station THEN
      RAISE EXCEPTION 'the login % may not add capture events (session %:%, event %): only the station''s technician pushes them',
        session_user, s.station, s.station_session_id, NEW.seq USING ERRCODE = '42501';
    END IF;
  END IF;
  IF s.status IN ('approved', 'rejected') THEN
    RAISE EXCEPTION 'session %:% was % by a curator: the decision is final and nothing follows it (event % refused)',
      s.station, s.station_session_id, s.status, NEW.seq
      USING ERRCODE = '42501', HINT = 'take the decision in with leafdig sync pull';
  END IF;
  IF review AND s.status <> 'complete' THEN
    RAISE EXCEPTION 'session %:% is %: only a complete session is corrected, approved or rejected (event %)',
      s.station, s.station_session_id, s.status, NEW.seq USING ERRCODE = '42501';
  END IF;
  IF NOT review AND s.status <> 'open' THEN
    RAISE EXCEPTION 'session %:% is %: its capture is over and only a curator adds to it (event % refused)',
      s.station, s.station_session_id, s.status, NEW.seq USING ERRCODE = '42501';
  END IF;
  IF NEW.kind IN ('undone', 'retake', 'corrected') THEN
    BEGIN
      SELECT e.kind INTO named_kind FROM leafdig.events e
       WHERE e.session_id = NEW.session_id AND e.seq = (NEW.payload_json::jsonb ->> 'seq')::bigint;
    EXCEPTION WHEN others THEN
      named_kind := NULL;  -- payload_problem names what is wrong
    END;
  END IF;
  problem := leafdig.payload_problem(NEW.kind, NEW.payload_json, NEW.seq, named_kind, s.kind);
  IF problem IS NULL AND NEW.kind = 'status' THEN
    new_status := NEW.payload_json::jsonb ->> 'status';
    IF NOT review AND new_status NOT IN ('complete', 'abandoned') THEN
      problem := 'a capture ends as complete or abandoned, not ' || new_status;
    END IF;
  END IF;
  IF problem IS NOT NULL THEN
    RAISE EXCEPTION 'session %:% event % (%) refused: %', s.station, s.station_session_id, NEW.seq,
      pg_catalog.left(NEW.kind, 40), problem
      USING ERRCODE = '22023', HINT = 'only what leafdig writes is taken (docs/schema.md, "Event kinds")';
  END IF;
  IF NEW.seq <> s.head_seq + 1 THEN
    RAISE EXCEPTION 'session %:% event % does not follow: the server holds events 1 to %', s.station,
      s.station_session_id, NEW.seq, s.head_seq USING ERRCODE = 'LD001';
  END IF;
  IF NEW.prev_hash IS DISTINCT FROM s.head_hash THEN
    RAISE EXCEPTION 'session %:% event % does not follow the server''s event % (another previous hash): the station''s copy and the server''s differ',
      s.station, s.station_session_id, NEW.seq, s.head_seq USING ERRCODE = 'LD001';
  END IF;
  IF NEW.hash IS DISTINCT FROM leafdig.chain_hash(NEW.prev_hash, s.station_session_id, NEW.seq, NEW.utc,
                                                  NEW.mono_ns, NEW.kind, NEW.payload_json, NEW.raw) THEN
    RAISE EXCEPTION 'session %:% event % does not hash to its hash: it was changed after it was written',
      s.station, s.station_session_id, NEW.seq USING ERRCODE = 'LD002';
  END IF;
  UPDATE leafdig.sessions x SET head_seq = NEW.seq, head_hash = NEW.hash, status = coalesce(new_status, x.status)
   WHERE x.id = s.id;
  NEW.written_by := session_user;
  NEW.received := pg_catalog.clock_timestamp();
  RETURN NEW;
END $$;

REVOKE INSERT ON leafdig.sessions FROM leafdig_technicians;
GRANT INSERT (station, station_session_id, project, plant, leaf_position, leaf_type, measured_area_mm2, operator,
              mode, capture_order, settings_json, created_utc, genesis_hash, kind) ON leafdig.sessions
  TO leafdig_technicians;
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
)SQL",
    // ---- version 4: a plant session's retakes (docs/server-schema.md, "Plant sessions") -------
    R"SQL(
-- A plant session takes `retake` (naming the event that put the item in: accepted or a
-- retake_cancelled) and `retake_cancelled` (the item put back, a plant's or a full leaf's), as a
-- leaf session does; an undo or a correction may name a retake_cancelled, which holds its item.
-- The rest is version 3's, word for word.
CREATE OR REPLACE FUNCTION leafdig.payload_problem(kind text, payload text, seq bigint, named_kind text, session_kind text)
  RETURNS text LANGUAGE plpgsql IMMUTABLE SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  p jsonb;
BEGIN
  IF session_kind = 'leaf' THEN
    IF kind IN ('landmarks_ended', 'landmarks_reopened', 'plant_ended', 'plant_reopened', 'leaf_chosen',
                'choice_undone') THEN
      RETURN 'it is a plant session''s event and this session captures one leaf';
    END IF;
    RETURN leafdig.payload_problem(kind, payload, seq, named_kind);
  END IF;
  IF kind NOT IN ('accepted', 'rejected', 'undone', 'retake', 'retake_cancelled', 'rows_ended', 'rows_reopened',
                  'corrected', 'paused', 'resumed', 'device', 'ignored_reading', 'status', 'landmarks_ended',
                  'landmarks_reopened', 'plant_ended', 'plant_reopened', 'leaf_chosen', 'choice_undone') THEN
    RETURN 'its kind is not one leafdig writes for a plant session';
  END IF;
  IF kind = 'status' THEN
    RETURN leafdig.payload_problem(kind, payload, seq, named_kind);  -- the same five words
  END IF;
  BEGIN
    p := payload::jsonb;
  EXCEPTION WHEN others THEN
    RETURN 'its payload is not JSON';
  END;
  IF pg_catalog.jsonb_typeof(p) <> 'object' THEN RETURN 'its payload is not a JSON object'; END IF;
  IF kind IN ('accepted', 'retake_cancelled') THEN
    IF NOT leafdig.is_plant_item(p) THEN
      RETURN 'its payload is not a plant''s item (landmark, collar, point, quick_point, collar_diameter, reading, or nodeK. before a leaf''s item)';
    END IF;
  ELSIF kind IN ('undone', 'retake', 'corrected') THEN
    IF coalesce(pg_catalog.jsonb_typeof(p -> 'seq'), '') <> 'number' OR (p ->> 'seq') !~ '^[0-9]+$'
       OR (p ->> 'seq')::numeric >= seq THEN
      RETURN 'its payload does not name an earlier event (seq)';
    END IF;
    IF kind = 'corrected' THEN
      IF named_kind IS NULL OR named_kind NOT IN ('accepted', 'retake_cancelled', 'corrected') THEN
        RETURN 'it corrects event ' || (p ->> 'seq') || ', which put no item in';
      END IF;
      IF NOT leafdig.is_plant_item(p -> 'corrected') OR coalesce(pg_catalog.jsonb_typeof(p -> 'reason'), '') <> 'string'
         OR coalesce(pg_catalog.jsonb_typeof(p -> 'who'), '') <> 'string' THEN
        RETURN 'its payload lacks the corrected item, the reason or who corrected';
      END IF;
    ELSIF named_kind IS NULL OR named_kind NOT IN ('accepted', 'retake_cancelled') THEN
      RETURN 'it takes back event ' || (p ->> 'seq') || ', which is not a captured item';
    END IF;
  ELSIF kind IN ('rows_ended', 'rows_reopened') THEN
    IF NOT leafdig.names_node(p) THEN RETURN 'its payload does not name the node whose leaf it is (node)'; END IF;
  ELSIF kind IN ('leaf_chosen', 'choice_undone') THEN
    IF NOT (leafdig.names_node(p) AND coalesce(p ->> 'kind', '') IN ('full', 'quick', 'none')
            AND coalesce(p ->> 'state', '') IN ('alive', 'dead', 'broken', 'yellow', 'pruned')
            AND (NOT p ? 'type' OR (pg_catalog.jsonb_typeof(p -> 'type') = 'string'
                                    AND pg_catalog.char_length(p ->> 'type') <= 64))) THEN
      RETURN 'its payload is not a leaf''s choice (node; kind full, quick or none; state alive, dead, broken, yellow or pruned; a type of at most 64 characters)';
    END IF;
  END IF;
  RETURN NULL;
END $$;
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
)SQL",
    // ---- version 5: a plant's branches (docs/server-schema.md, "Plant sessions") ------------
    R"SQL(
-- A plant session takes `node_placed` and `placement_undone` ({"node", "parent" (a node before
-- it), "relation" < or +}: where a node hangs, a branch begun or ended); a leaf session does
-- not. The rest is version 4's, word for word.
CREATE OR REPLACE FUNCTION leafdig.payload_problem(kind text, payload text, seq bigint, named_kind text, session_kind text)
  RETURNS text LANGUAGE plpgsql IMMUTABLE SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  p jsonb;
BEGIN
  IF session_kind = 'leaf' THEN
    IF kind IN ('landmarks_ended', 'landmarks_reopened', 'plant_ended', 'plant_reopened', 'leaf_chosen',
                'choice_undone', 'node_placed', 'placement_undone') THEN
      RETURN 'it is a plant session''s event and this session captures one leaf';
    END IF;
    RETURN leafdig.payload_problem(kind, payload, seq, named_kind);
  END IF;
  IF kind NOT IN ('accepted', 'rejected', 'undone', 'retake', 'retake_cancelled', 'rows_ended', 'rows_reopened',
                  'corrected', 'paused', 'resumed', 'device', 'ignored_reading', 'status', 'landmarks_ended',
                  'landmarks_reopened', 'plant_ended', 'plant_reopened', 'leaf_chosen', 'choice_undone',
                  'node_placed', 'placement_undone') THEN
    RETURN 'its kind is not one leafdig writes for a plant session';
  END IF;
  IF kind = 'status' THEN
    RETURN leafdig.payload_problem(kind, payload, seq, named_kind);  -- the same five words
  END IF;
  BEGIN
    p := payload::jsonb;
  EXCEPTION WHEN others THEN
    RETURN 'its payload is not JSON';
  END;
  IF pg_catalog.jsonb_typeof(p) <> 'object' THEN RETURN 'its payload is not a JSON object'; END IF;
  IF kind IN ('accepted', 'retake_cancelled') THEN
    IF NOT leafdig.is_plant_item(p) THEN
      RETURN 'its payload is not a plant''s item (landmark, collar, point, quick_point, collar_diameter, reading, or nodeK. before a leaf''s item)';
    END IF;
  ELSIF kind IN ('undone', 'retake', 'corrected') THEN
    IF coalesce(pg_catalog.jsonb_typeof(p -> 'seq'), '') <> 'number' OR (p ->> 'seq') !~ '^[0-9]+$'
       OR (p ->> 'seq')::numeric >= seq THEN
      RETURN 'its payload does not name an earlier event (seq)';
    END IF;
    IF kind = 'corrected' THEN
      IF named_kind IS NULL OR named_kind NOT IN ('accepted', 'retake_cancelled', 'corrected') THEN
        RETURN 'it corrects event ' || (p ->> 'seq') || ', which put no item in';
      END IF;
      IF NOT leafdig.is_plant_item(p -> 'corrected') OR coalesce(pg_catalog.jsonb_typeof(p -> 'reason'), '') <> 'string'
         OR coalesce(pg_catalog.jsonb_typeof(p -> 'who'), '') <> 'string' THEN
        RETURN 'its payload lacks the corrected item, the reason or who corrected';
      END IF;
    ELSIF named_kind IS NULL OR named_kind NOT IN ('accepted', 'retake_cancelled') THEN
      RETURN 'it takes back event ' || (p ->> 'seq') || ', which is not a captured item';
    END IF;
  ELSIF kind IN ('rows_ended', 'rows_reopened') THEN
    IF NOT leafdig.names_node(p) THEN RETURN 'its payload does not name the node whose leaf it is (node)'; END IF;
  ELSIF kind IN ('leaf_chosen', 'choice_undone') THEN
    IF NOT (leafdig.names_node(p) AND coalesce(p ->> 'kind', '') IN ('full', 'quick', 'none')
            AND coalesce(p ->> 'state', '') IN ('alive', 'dead', 'broken', 'yellow', 'pruned')
            AND (NOT p ? 'type' OR (pg_catalog.jsonb_typeof(p -> 'type') = 'string'
                                    AND pg_catalog.char_length(p ->> 'type') <= 64))) THEN
      RETURN 'its payload is not a leaf''s choice (node; kind full, quick or none; state alive, dead, broken, yellow or pruned; a type of at most 64 characters)';
    END IF;
  ELSIF kind IN ('node_placed', 'placement_undone') THEN
    IF NOT (leafdig.names_node(p) AND coalesce(pg_catalog.jsonb_typeof(p -> 'parent'), '') = 'number'
            AND coalesce(p ->> 'relation', '') IN ('<', '+')
            AND CASE WHEN (p ->> 'parent') ~ '^[1-9][0-9]{0,3}$' AND (p ->> 'node') ~ '^[1-9][0-9]{0,3}$'
                     THEN (p ->> 'parent')::int < (p ->> 'node')::int ELSE false END) THEN
      RETURN 'its payload is not where a node hangs (node; parent, a node before it; relation < or +)';
    END IF;
  END IF;
  RETURN NULL;
END $$;
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
)SQL",
    // ---- version 6: moving the transmitter (docs/server-schema.md, "Plant sessions") ---------
    R"SQL(
-- A plant session takes `relocation` ({"relocation": 1…999, "step": started, fitted, reopened
-- or cancelled}) and the landmarks taken again after a move, `accepted` landmark_again items
-- (a position, like a landmark), each item with an optional transmitter position `frame`; a
-- leaf session takes neither. The rest is version 5's, word for word.
CREATE OR REPLACE FUNCTION leafdig.is_plant_item(item jsonb) RETURNS boolean LANGUAGE sql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
  SELECT coalesce(CASE
    WHEN pg_catalog.jsonb_typeof(item) <> 'object' THEN false
    WHEN coalesce(item ->> 'what', '') ~ '^node[1-9][0-9]{0,3}\.[a-z_]+$' THEN
      pg_catalog.split_part(item ->> 'what', '.', 2) <> 'board'
      AND leafdig.is_item(item || pg_catalog.jsonb_build_object('what', pg_catalog.split_part(item ->> 'what', '.', 2)))
    ELSE coalesce(item ->> 'what', '') IN ('landmark', 'collar', 'point', 'quick_point', 'collar_diameter', 'reading',
                                            'landmark_again')
      AND coalesce(pg_catalog.jsonb_typeof(item -> 'row'), 'null') IN ('null', 'number')
      AND coalesce(pg_catalog.jsonb_typeof(item -> 'col'), 'null') IN ('null', 'number')
      AND (NOT item ? 'frame' OR (pg_catalog.jsonb_typeof(item -> 'frame') = 'number'
                                  AND (item ->> 'frame') ~ '^[0-9]{1,3}$'))
      AND CASE WHEN item ->> 'what' IN ('landmark', 'collar', 'point', 'quick_point', 'landmark_again')
               THEN pg_catalog.jsonb_typeof(item -> 'position_mm') = 'array'
                    AND pg_catalog.jsonb_array_length(item -> 'position_mm') = 3
                    AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 0) = 'number'
                    AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 1) = 'number'
                    AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 2) = 'number'
               ELSE pg_catalog.jsonb_typeof(item -> 'value_mm') = 'number' AND (item ->> 'value_mm')::numeric > 0
          END
  END, false) $$;

CREATE OR REPLACE FUNCTION leafdig.payload_problem(kind text, payload text, seq bigint, named_kind text, session_kind text)
  RETURNS text LANGUAGE plpgsql IMMUTABLE SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  p jsonb;
BEGIN
  IF session_kind = 'leaf' THEN
    IF kind IN ('landmarks_ended', 'landmarks_reopened', 'plant_ended', 'plant_reopened', 'leaf_chosen',
                'choice_undone', 'node_placed', 'placement_undone', 'relocation') THEN
      RETURN 'it is a plant session''s event and this session captures one leaf';
    END IF;
    RETURN leafdig.payload_problem(kind, payload, seq, named_kind);
  END IF;
  IF kind NOT IN ('accepted', 'rejected', 'undone', 'retake', 'retake_cancelled', 'rows_ended', 'rows_reopened',
                  'corrected', 'paused', 'resumed', 'device', 'ignored_reading', 'status', 'landmarks_ended',
                  'landmarks_reopened', 'plant_ended', 'plant_reopened', 'leaf_chosen', 'choice_undone',
                  'node_placed', 'placement_undone', 'relocation') THEN
    RETURN 'its kind is not one leafdig writes for a plant session';
  END IF;
  IF kind = 'status' THEN
    RETURN leafdig.payload_problem(kind, payload, seq, named_kind);  -- the same five words
  END IF;
  BEGIN
    p := payload::jsonb;
  EXCEPTION WHEN others THEN
    RETURN 'its payload is not JSON';
  END;
  IF pg_catalog.jsonb_typeof(p) <> 'object' THEN RETURN 'its payload is not a JSON object'; END IF;
  IF kind IN ('accepted', 'retake_cancelled') THEN
    IF NOT leafdig.is_plant_item(p) THEN
      RETURN 'its payload is not a plant''s item (landmark, collar, point, quick_point, collar_diameter, reading, or nodeK. before a leaf''s item)';
    END IF;
  ELSIF kind IN ('undone', 'retake', 'corrected') THEN
    IF coalesce(pg_catalog.jsonb_typeof(p -> 'seq'), '') <> 'number' OR (p ->> 'seq') !~ '^[0-9]+$'
       OR (p ->> 'seq')::numeric >= seq THEN
      RETURN 'its payload does not name an earlier event (seq)';
    END IF;
    IF kind = 'corrected' THEN
      IF named_kind IS NULL OR named_kind NOT IN ('accepted', 'retake_cancelled', 'corrected') THEN
        RETURN 'it corrects event ' || (p ->> 'seq') || ', which put no item in';
      END IF;
      IF NOT leafdig.is_plant_item(p -> 'corrected') OR coalesce(pg_catalog.jsonb_typeof(p -> 'reason'), '') <> 'string'
         OR coalesce(pg_catalog.jsonb_typeof(p -> 'who'), '') <> 'string' THEN
        RETURN 'its payload lacks the corrected item, the reason or who corrected';
      END IF;
    ELSIF named_kind IS NULL OR named_kind NOT IN ('accepted', 'retake_cancelled') THEN
      RETURN 'it takes back event ' || (p ->> 'seq') || ', which is not a captured item';
    END IF;
  ELSIF kind IN ('rows_ended', 'rows_reopened') THEN
    IF NOT leafdig.names_node(p) THEN RETURN 'its payload does not name the node whose leaf it is (node)'; END IF;
  ELSIF kind IN ('leaf_chosen', 'choice_undone') THEN
    IF NOT (leafdig.names_node(p) AND coalesce(p ->> 'kind', '') IN ('full', 'quick', 'none')
            AND coalesce(p ->> 'state', '') IN ('alive', 'dead', 'broken', 'yellow', 'pruned')
            AND (NOT p ? 'type' OR (pg_catalog.jsonb_typeof(p -> 'type') = 'string'
                                    AND pg_catalog.char_length(p ->> 'type') <= 64))) THEN
      RETURN 'its payload is not a leaf''s choice (node; kind full, quick or none; state alive, dead, broken, yellow or pruned; a type of at most 64 characters)';
    END IF;
  ELSIF kind IN ('node_placed', 'placement_undone') THEN
    IF NOT (leafdig.names_node(p) AND coalesce(pg_catalog.jsonb_typeof(p -> 'parent'), '') = 'number'
            AND coalesce(p ->> 'relation', '') IN ('<', '+')
            AND CASE WHEN (p ->> 'parent') ~ '^[1-9][0-9]{0,3}$' AND (p ->> 'node') ~ '^[1-9][0-9]{0,3}$'
                     THEN (p ->> 'parent')::int < (p ->> 'node')::int ELSE false END) THEN
      RETURN 'its payload is not where a node hangs (node; parent, a node before it; relation < or +)';
    END IF;
  ELSIF kind = 'relocation' THEN
    IF NOT (coalesce(pg_catalog.jsonb_typeof(p -> 'relocation'), '') = 'number'
            AND (p ->> 'relocation') ~ '^[1-9][0-9]{0,2}$'
            AND coalesce(p ->> 'step', '') IN ('started', 'fitted', 'reopened', 'cancelled')) THEN
      RETURN 'its payload is not a move of the transmitter (relocation 1 to 999; step started, fitted, reopened or cancelled)';
    END IF;
  END IF;
  RETURN NULL;
END $$;
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
)SQL",
    // ---- version 7: a leaf's transmitter moved (docs/server-schema.md, "Version 7") -------------
    R"SQL(
-- A leaf session takes `relocation` (the plant's payload) and `accepted` / `retake_cancelled`
-- board_again items (a board point taken again after the move: a position, its relocation as
-- the row, the board point as the col); a leaf's item may carry a transmitter position `frame`
-- (a small whole number). A board_again item is never corrected. Version 6's function keeps
-- the plant's rules and the rest, renamed; this one sees the leaf's new events first.
ALTER FUNCTION leafdig.payload_problem(text, text, bigint, text, text) RENAME TO payload_problem_v6;

CREATE FUNCTION leafdig.is_relocation(p jsonb) RETURNS boolean LANGUAGE sql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
  SELECT coalesce(pg_catalog.jsonb_typeof(p) = 'object'
     AND coalesce(pg_catalog.jsonb_typeof(p -> 'relocation'), '') = 'number'
     AND (p ->> 'relocation') ~ '^[1-9][0-9]{0,2}$'
     AND coalesce(p ->> 'step', '') IN ('started', 'fitted', 'reopened', 'cancelled'), false) $$;

CREATE FUNCTION leafdig.is_leaf_item(item jsonb) RETURNS boolean LANGUAGE sql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
  SELECT coalesce(pg_catalog.jsonb_typeof(item) = 'object'
     AND (NOT item ? 'frame' OR (pg_catalog.jsonb_typeof(item -> 'frame') = 'number'
                                 AND (item ->> 'frame') ~ '^[0-9]{1,3}$'))
     AND CASE WHEN item ->> 'what' = 'board_again'
              THEN pg_catalog.jsonb_typeof(item -> 'row') = 'number' AND (item ->> 'row') ~ '^[1-9][0-9]{0,2}$'
                   AND pg_catalog.jsonb_typeof(item -> 'col') = 'number' AND (item ->> 'col') IN ('1', '2', '3')
                   AND leafdig.is_item(item || '{"what": "board"}'::jsonb)
              ELSE leafdig.is_item(item) END, false) $$;

CREATE FUNCTION leafdig.payload_problem(kind text, payload text, seq bigint, named_kind text, session_kind text)
  RETURNS text LANGUAGE plpgsql IMMUTABLE SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  p jsonb;
BEGIN
  IF session_kind = 'leaf' AND kind IN ('relocation', 'accepted', 'retake_cancelled') THEN
    BEGIN
      p := payload::jsonb;
    EXCEPTION WHEN others THEN
      RETURN 'its payload is not JSON';
    END;
    IF pg_catalog.jsonb_typeof(p) <> 'object' THEN RETURN 'its payload is not a JSON object'; END IF;
    IF kind = 'relocation' THEN
      IF NOT leafdig.is_relocation(p) THEN
        RETURN 'its payload is not a move of the transmitter (relocation 1 to 999; step started, fitted, reopened or cancelled)';
      END IF;
      RETURN NULL;
    END IF;
    IF NOT leafdig.is_leaf_item(p) THEN
      RETURN 'its payload is not an item (what, row, col, position_mm or value_mm; a frame of 0 to 999)';
    END IF;
    RETURN NULL;
  END IF;
  RETURN leafdig.payload_problem_v6(kind, payload, seq, named_kind, session_kind);
END $$;
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
)SQL",
    // ---- version 8: a board point corrected after a move (docs/server-schema.md, "Version 8") ---
    R"SQL(
-- A curator corrects a leaf's board point taken again after a move (board_again) like any
-- other item: the points that move placed are corrected with it, each by its own event, in one
-- transaction. A leaf's corrected item is checked as its accepted items are (is_leaf_item).
ALTER FUNCTION leafdig.payload_problem(text, text, bigint, text, text) RENAME TO payload_problem_v7;

CREATE FUNCTION leafdig.payload_problem(kind text, payload text, seq bigint, named_kind text, session_kind text)
  RETURNS text LANGUAGE plpgsql IMMUTABLE SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  p jsonb;
BEGIN
  IF session_kind = 'leaf' AND kind = 'corrected' THEN
    BEGIN
      p := payload::jsonb;
    EXCEPTION WHEN others THEN
      RETURN 'its payload is not JSON';
    END;
    IF pg_catalog.jsonb_typeof(p) <> 'object' THEN RETURN 'its payload is not a JSON object'; END IF;
    IF coalesce(pg_catalog.jsonb_typeof(p -> 'seq'), '') <> 'number' OR (p ->> 'seq') !~ '^[0-9]+$'
       OR (p ->> 'seq')::numeric >= seq THEN
      RETURN 'its payload does not name an earlier event (seq)';
    END IF;
    IF named_kind IS NULL OR named_kind NOT IN ('accepted', 'retake_cancelled', 'corrected') THEN
      RETURN 'it corrects event ' || (p ->> 'seq') || ', which put no item in';
    END IF;
    IF NOT leafdig.is_leaf_item(p -> 'corrected') OR coalesce(pg_catalog.jsonb_typeof(p -> 'reason'), '') <> 'string'
       OR coalesce(pg_catalog.jsonb_typeof(p -> 'who'), '') <> 'string' THEN
      RETURN 'its payload lacks the corrected item, the reason or who corrected';
    END IF;
    IF coalesce(p ->> 'what', '') <> coalesce(p -> 'corrected' ->> 'what', '')
       OR coalesce(p ->> 'row', '') <> coalesce(p -> 'corrected' ->> 'row', '')
       OR coalesce(p ->> 'col', '') <> coalesce(p -> 'corrected' ->> 'col', '') THEN
      RETURN 'its corrected item is not the item it names (what, row, col)';
    END IF;
    RETURN NULL;
  END IF;
  RETURN leafdig.payload_problem_v7(kind, payload, seq, named_kind, session_kind);
END $$;
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
)SQL",
    // ---- version 9: a push checked a statement at a time (docs/server-schema.md, "Version 9") ---
    R"SQL(
-- A push is checked a statement at a time. Until version 8 every event ran the whole check
-- on arrival: the session's row locked and moved, the login's groups looked up, its kind and
-- payload checked through SQL functions that PostgreSQL plans again at every call (a SQL
-- function with a SET clause is never inlined), the chain's SHA-256 — about 130 µs an event.
-- Now:
--   * before each row (event_arrives): what a constraint would otherwise refuse first in
--     other words — the session the login may see, its station, who may add what, in which
--     state of the session, an event the server holds already — read, not locked;
--   * after each statement (events_arrived, over the statement's rows): the sessions it adds
--     to, locked once in the order of their ids; each session's rows in order of seq with the
--     same checks as before (the session's state as the statement's own status events leave
--     it, kind and payload, the chain and the hash) and the head and status moved once.
-- An exception in either undoes the whole statement, as before; the words are version 8's.
-- The helpers are the same expressions in PL/pgSQL, whose plans are kept for the connection.
CREATE OR REPLACE FUNCTION leafdig.is_admin(who name) RETURNS boolean LANGUAGE plpgsql STABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN coalesce((SELECT r.rolsuper FROM pg_catalog.pg_roles r WHERE r.rolname = who), false)
      OR pg_catalog.pg_has_role(who, (SELECT n.nspowner FROM pg_catalog.pg_namespace n WHERE n.nspname = 'leafdig'),
                                'MEMBER');
END $$;
CREATE OR REPLACE FUNCTION leafdig.login_station(who name) RETURNS text LANGUAGE plpgsql STABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN (SELECT l.station FROM leafdig.station_logins l WHERE l.login = who);
END $$;
CREATE OR REPLACE FUNCTION leafdig.chain_hash(prev text, station_session bigint, seq bigint, utc text, mono bigint,
                                              kind text, payload text, raw text) RETURNS text LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN pg_catalog.encode(pg_catalog.sha256(pg_catalog.convert_to(
           prev || E'\n' || station_session || E'\n' || seq || E'\n' || utc || E'\n' || mono || E'\n' || kind ||
           E'\n' || pg_catalog.octet_length(payload) || ':' || payload || E'\n' || pg_catalog.octet_length(raw) ||
           ':' || raw, 'UTF8')), 'hex');
END $$;
CREATE OR REPLACE FUNCTION leafdig.is_item(item jsonb) RETURNS boolean LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN coalesce(pg_catalog.jsonb_typeof(item) = 'object'
     AND coalesce(item ->> 'what', '') IN ('board', 'tip', 'marker', 'midrib_thickness', 'vein_origin_thickness',
                                           'edge_thickness', 'point_thickness')
     AND coalesce(pg_catalog.jsonb_typeof(item -> 'row'), 'null') IN ('null', 'number')
     AND coalesce(pg_catalog.jsonb_typeof(item -> 'col'), 'null') IN ('null', 'number')
     AND CASE WHEN item ->> 'what' IN ('board', 'tip', 'marker')
              THEN pg_catalog.jsonb_typeof(item -> 'position_mm') = 'array'
                   AND pg_catalog.jsonb_array_length(item -> 'position_mm') = 3
                   AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 0) = 'number'
                   AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 1) = 'number'
                   AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 2) = 'number'
              ELSE pg_catalog.jsonb_typeof(item -> 'value_mm') = 'number' AND (item ->> 'value_mm')::numeric > 0
         END, false);
END $$;
CREATE OR REPLACE FUNCTION leafdig.is_leaf_item(item jsonb) RETURNS boolean LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN coalesce(pg_catalog.jsonb_typeof(item) = 'object'
     AND (NOT item ? 'frame' OR (pg_catalog.jsonb_typeof(item -> 'frame') = 'number'
                                 AND (item ->> 'frame') ~ '^[0-9]{1,3}$'))
     AND CASE WHEN item ->> 'what' = 'board_again'
              THEN pg_catalog.jsonb_typeof(item -> 'row') = 'number' AND (item ->> 'row') ~ '^[1-9][0-9]{0,2}$'
                   AND pg_catalog.jsonb_typeof(item -> 'col') = 'number' AND (item ->> 'col') IN ('1', '2', '3')
                   AND leafdig.is_item(item || '{"what": "board"}'::jsonb)
              ELSE leafdig.is_item(item) END, false);
END $$;
CREATE OR REPLACE FUNCTION leafdig.is_plant_item(item jsonb) RETURNS boolean LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN coalesce(CASE
    WHEN pg_catalog.jsonb_typeof(item) <> 'object' THEN false
    WHEN coalesce(item ->> 'what', '') ~ '^node[1-9][0-9]{0,3}\.[a-z_]+$' THEN
      pg_catalog.split_part(item ->> 'what', '.', 2) <> 'board'
      AND leafdig.is_item(item || pg_catalog.jsonb_build_object('what', pg_catalog.split_part(item ->> 'what', '.', 2)))
    ELSE coalesce(item ->> 'what', '') IN ('landmark', 'collar', 'point', 'quick_point', 'collar_diameter', 'reading',
                                            'landmark_again')
      AND coalesce(pg_catalog.jsonb_typeof(item -> 'row'), 'null') IN ('null', 'number')
      AND coalesce(pg_catalog.jsonb_typeof(item -> 'col'), 'null') IN ('null', 'number')
      AND (NOT item ? 'frame' OR (pg_catalog.jsonb_typeof(item -> 'frame') = 'number'
                                  AND (item ->> 'frame') ~ '^[0-9]{1,3}$'))
      AND CASE WHEN item ->> 'what' IN ('landmark', 'collar', 'point', 'quick_point', 'landmark_again')
               THEN pg_catalog.jsonb_typeof(item -> 'position_mm') = 'array'
                    AND pg_catalog.jsonb_array_length(item -> 'position_mm') = 3
                    AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 0) = 'number'
                    AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 1) = 'number'
                    AND pg_catalog.jsonb_typeof(item -> 'position_mm' -> 2) = 'number'
               ELSE pg_catalog.jsonb_typeof(item -> 'value_mm') = 'number' AND (item ->> 'value_mm')::numeric > 0
          END
  END, false);
END $$;
CREATE OR REPLACE FUNCTION leafdig.names_node(p jsonb) RETURNS boolean LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN coalesce(pg_catalog.jsonb_typeof(p -> 'node') = 'number' AND (p ->> 'node') ~ '^[1-9][0-9]{0,3}$', false);
END $$;
CREATE OR REPLACE FUNCTION leafdig.is_relocation(p jsonb) RETURNS boolean LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN coalesce(pg_catalog.jsonb_typeof(p) = 'object'
     AND coalesce(pg_catalog.jsonb_typeof(p -> 'relocation'), '') = 'number'
     AND (p ->> 'relocation') ~ '^[1-9][0-9]{0,2}$'
     AND coalesce(p ->> 'step', '') IN ('started', 'fitted', 'reopened', 'cancelled'), false);
END $$;

-- A curator's event: a correction, or a status of approved or rejected. The kinds are told
-- apart before the block that catches a payload that is not JSON (entering such a block costs
-- a subtransaction, on every row the policies and triggers ask).
CREATE OR REPLACE FUNCTION leafdig.is_review_event(kind text, payload text) RETURNS boolean LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  IF kind = 'corrected' THEN RETURN true; END IF;
  IF kind IS DISTINCT FROM 'status' THEN RETURN false; END IF;
  BEGIN
    RETURN coalesce((payload::jsonb ->> 'status') IN ('approved', 'rejected'), false);
  EXCEPTION WHEN others THEN
    RETURN false;  -- not JSON: not a review event (the arrival check refuses it by name)
  END;
END $$;

-- The policies ask the login's station once per statement (an InitPlan), not once per row.
ALTER POLICY push_own ON leafdig.events
  WITH CHECK (station = (SELECT leafdig.login_station(current_user)) AND NOT leafdig.is_review_event(kind, payload_json));

-- The event an undo, retake or correction names (its payload's "seq"), or NULL.
CREATE FUNCTION leafdig.named_seq(payload text) RETURNS bigint LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN (payload::jsonb ->> 'seq')::bigint;
EXCEPTION WHEN others THEN
  RETURN NULL;  -- payload_problem names what is wrong
END $$;

-- Who may add what, in which state of the session (version 3's words): raises, or returns.
-- `s` is the session (NULL when there is none), `state` its status as the event finds it.
CREATE FUNCTION leafdig.refuse_arrival(session_id bigint, s leafdig.sessions, station text, seq bigint,
                                       review boolean, state text, admin boolean, curator boolean,
                                       technician boolean, bound text) RETURNS void LANGUAGE plpgsql STABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  -- What a login may not see does not exist for it: the same words for both.
  IF s.id IS NULL OR NOT (admin OR curator OR (technician AND bound IS NOT DISTINCT FROM s.station)) THEN
    IF NOT (admin OR curator OR technician) THEN
      RAISE EXCEPTION 'the login % may not add events: it only reads', session_user USING ERRCODE = '42501';
    END IF;
    RAISE EXCEPTION 'there is no session % on the server that the login % may add to', session_id, session_user
      USING ERRCODE = 'LD003';
  END IF;
  IF station IS DISTINCT FROM s.station THEN
    RAISE EXCEPTION 'event % names station % but session %:% is station %''s', seq, station, s.station,
      s.station_session_id, s.station USING ERRCODE = '42501';
  END IF;
  IF NOT admin THEN
    IF review THEN
      IF NOT curator THEN
        RAISE EXCEPTION 'the login % may not approve, reject or correct sessions (session %:%, event %): only curators review',
          session_user, s.station, s.station_session_id, seq
          USING ERRCODE = '42501', HINT = 'a curator reviews on the server (leafdig sessions approve --db postgresql://…) and the station takes the decision in with leafdig sync pull';
      END IF;
    ELSIF NOT technician OR bound IS DISTINCT FROM s.station THEN
      RAISE EXCEPTION 'the login % may not add capture events (session %:%, event %): only the station''s technician pushes them',
        session_user, s.station, s.station_session_id, seq USING ERRCODE = '42501';
    END IF;
  END IF;
  IF state IN ('approved', 'rejected') THEN
    RAISE EXCEPTION 'session %:% was % by a curator: the decision is final and nothing follows it (event % refused)',
      s.station, s.station_session_id, state, seq
      USING ERRCODE = '42501', HINT = 'take the decision in with leafdig sync pull';
  END IF;
  IF review AND state <> 'complete' THEN
    RAISE EXCEPTION 'session %:% is %: only a complete session is corrected, approved or rejected (event %)',
      s.station, s.station_session_id, state, seq USING ERRCODE = '42501';
  END IF;
  IF NOT review AND state <> 'open' THEN
    RAISE EXCEPTION 'session %:% is %: its capture is over and only a curator adds to it (event % refused)',
      s.station, s.station_session_id, state, seq USING ERRCODE = '42501';
  END IF;
END $$;

-- Before each row: the words a constraint would otherwise pre-empt, and the server's stamps.
CREATE OR REPLACE FUNCTION leafdig.event_arrives() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  s leafdig.sessions;
BEGIN
  SELECT x.* INTO s FROM leafdig.sessions x WHERE x.id = NEW.session_id;
  -- The station's technician adding a capture event to its open session passes every rule of
  -- refuse_arrival; anything else is asked in full.
  IF NOT (FOUND AND NEW.station = s.station AND s.status = 'open' AND NEW.kind NOT IN ('corrected', 'status')
          AND pg_catalog.pg_has_role(session_user, 'leafdig_technicians', 'MEMBER')
          AND leafdig.login_station(session_user) = s.station) THEN
    PERFORM leafdig.refuse_arrival(NEW.session_id, s, NEW.station, NEW.seq,
                                   leafdig.is_review_event(NEW.kind, NEW.payload_json), s.status,
                                   leafdig.is_admin(session_user),
                                   pg_catalog.pg_has_role(session_user, 'leafdig_curators', 'MEMBER'),
                                   pg_catalog.pg_has_role(session_user, 'leafdig_technicians', 'MEMBER'),
                                   leafdig.login_station(session_user));
  END IF;
  IF NEW.seq <= s.head_seq THEN
    RAISE EXCEPTION 'session %:% event % does not follow: the server holds events 1 to %', s.station,
      s.station_session_id, NEW.seq, s.head_seq USING ERRCODE = 'LD001';
  END IF;
  NEW.written_by := session_user;
  NEW.received := pg_catalog.clock_timestamp();
  RETURN NEW;
END $$;

-- After each statement: every check of version 8 over the statement's rows, the head moved once.
CREATE FUNCTION leafdig.events_arrived() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  admin boolean := leafdig.is_admin(session_user);
  curator boolean := pg_catalog.pg_has_role(session_user, 'leafdig_curators', 'MEMBER');
  technician boolean := pg_catalog.pg_has_role(session_user, 'leafdig_technicians', 'MEMBER');
  bound text := leafdig.login_station(session_user);
  s leafdig.sessions;
  e record;
  last_seq bigint;
  last_hash text;
  state text;
  new_status text;
  capturer boolean;
BEGIN
  FOR s IN SELECT x.* FROM leafdig.sessions x WHERE x.id IN (SELECT a.session_id FROM arrived a)
            ORDER BY x.id FOR UPDATE LOOP
    capturer := technician AND bound IS NOT DISTINCT FROM s.station;  -- refuse_arrival passes its capture
    last_seq := s.head_seq;
    last_hash := s.head_hash;
    state := s.status;
    FOR e IN SELECT a.seq, a.station, a.utc, a.mono_ns, a.kind, a.payload_json, a.raw, a.prev_hash, a.hash,
                    leafdig.is_review_event(a.kind, a.payload_json) AS review,
                    leafdig.payload_problem(a.kind, a.payload_json, a.seq,
                      CASE WHEN a.kind IN ('undone', 'retake', 'corrected')
                           THEN (SELECT n.kind FROM leafdig.events n
                                  WHERE n.session_id = s.id AND n.seq = leafdig.named_seq(a.payload_json)) END,
                      s.kind) AS problem
               FROM arrived a WHERE a.session_id = s.id ORDER BY a.seq LOOP
      IF NOT (capturer AND NOT e.review AND state = 'open' AND e.station = s.station) THEN
        PERFORM leafdig.refuse_arrival(s.id, s, e.station, e.seq, e.review, state, admin, curator, technician, bound);
      END IF;
      new_status := NULL;
      IF e.problem IS NULL AND e.kind = 'status' THEN
        new_status := e.payload_json::jsonb ->> 'status';
        IF NOT e.review AND new_status NOT IN ('complete', 'abandoned') THEN
          e.problem := 'a capture ends as complete or abandoned, not ' || new_status;
        END IF;
      END IF;
      IF e.problem IS NOT NULL THEN
        RAISE EXCEPTION 'session %:% event % (%) refused: %', s.station, s.station_session_id, e.seq,
          pg_catalog.left(e.kind, 40), e.problem
          USING ERRCODE = '22023', HINT = 'only what leafdig writes is taken (docs/schema.md, "Event kinds")';
      END IF;
      IF e.seq <> last_seq + 1 THEN
        RAISE EXCEPTION 'session %:% event % does not follow: the server holds events 1 to %', s.station,
          s.station_session_id, e.seq, last_seq USING ERRCODE = 'LD001';
      END IF;
      IF e.prev_hash IS DISTINCT FROM last_hash THEN
        RAISE EXCEPTION 'session %:% event % does not follow the server''s event % (another previous hash): the station''s copy and the server''s differ',
          s.station, s.station_session_id, e.seq, last_seq USING ERRCODE = 'LD001';
      END IF;
      IF e.hash IS DISTINCT FROM leafdig.chain_hash(e.prev_hash, s.station_session_id, e.seq, e.utc, e.mono_ns, e.kind,
                                                    e.payload_json, e.raw) THEN
        RAISE EXCEPTION 'session %:% event % does not hash to its hash: it was changed after it was written',
          s.station, s.station_session_id, e.seq USING ERRCODE = 'LD002';
      END IF;
      last_seq := e.seq;
      last_hash := e.hash;
      state := coalesce(new_status, state);
    END LOOP;
    UPDATE leafdig.sessions x SET head_seq = last_seq, head_hash = last_hash, status = state
     WHERE x.id = s.id;
  END LOOP;
  RETURN NULL;
END $$;
CREATE TRIGGER events_arrived AFTER INSERT ON leafdig.events REFERENCING NEW TABLE AS arrived
  FOR EACH STATEMENT EXECUTE FUNCTION leafdig.events_arrived();
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
)SQL",
    // ---- version 10: no login can make a session unreadable (docs/server-schema.md, "Version 10") ---
    R"SQL(
-- What leafdig's own replay refuses, the server refuses too (tests/data/event_cases.json holds
-- the cases both run):
--   * a payload of at most 64 KiB and a raw text of at most 256 KiB, a session's settings of
--     at most 4 MiB; every number in them within ±1e15 (a double holds it exactly; a duration in
--     nanoseconds of days fits); settings that are a JSON object;
--   * an item (accepted, retake_cancelled, undone, retake, corrected and its corrected item)
--     with no key leafdig does not write;
--   * an undo, a retake or a correction of the item that is there: the event it names put the
--     item in and still holds it (nothing undid, retook or corrected it since), and the payload
--     carries that item's what, row and col — as the corrected item does;
--   * a curator's decision or correction is signed by its own login: `who` may be a display
--     name but never another login than the one writing it (written_by), and no login that is
--     the technician of the session's station reviews it.
-- It may run again over itself (every statement replaces what it makes).
CREATE OR REPLACE FUNCTION leafdig.numbers_in_range(p jsonb) RETURNS boolean LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN NOT pg_catalog.jsonb_path_exists(p, 'strict $.** ? (@.type() == "number" && (@ > 1000000000000000 || @ < -1000000000000000))');
END $$;

-- The item an event puts in or takes out, as "what|row|col" (a correction: its corrected item).
CREATE OR REPLACE FUNCTION leafdig.item_key(item jsonb) RETURNS text LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN coalesce(item ->> 'what', '') || '|' || coalesce(item ->> 'row', '') || '|' || coalesce(item ->> 'col', '');
END $$;
CREATE OR REPLACE FUNCTION leafdig.event_item_key(kind text, payload text) RETURNS text LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  IF kind = 'corrected' THEN RETURN leafdig.item_key(payload::jsonb -> 'corrected'); END IF;
  RETURN leafdig.item_key(payload::jsonb);
EXCEPTION WHEN others THEN
  RETURN NULL;
END $$;

-- Where a leaf's item may stand (the capture's steps; a plant's full leaf's "nodeK.marker" as a
-- leaf's): NULL when it may, else what is wrong. A plant's own items are not a leaf's: NULL.
CREATE OR REPLACE FUNCTION leafdig.leaf_place_problem(item jsonb) RETURNS text LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  w text := pg_catalog.regexp_replace(coalesce(item ->> 'what', ''), '^node[1-9][0-9]{0,3}\.', '');
  r text := coalesce(item ->> 'row', '');
  c text := coalesce(item ->> 'col', '');
  row_ok boolean := r ~ '^[1-9][0-9]{0,3}$' AND r::integer <= 1000;
  ok boolean;
BEGIN
  ok := CASE w
    WHEN 'board' THEN r = '' AND c IN ('1', '2', '3')
    WHEN 'board_again' THEN r ~ '^[1-9][0-9]{0,2}$' AND c IN ('1', '2', '3')
    WHEN 'tip' THEN r = '' AND c = ''
    WHEN 'edge_thickness' THEN r = '' AND c = ''
    WHEN 'marker' THEN row_ok AND c IN ('1', '2', '3', '4', '5', '6', '7')
    WHEN 'point_thickness' THEN row_ok AND c IN ('1', '2', '3', '4', '5', '6', '7')
    WHEN 'midrib_thickness' THEN row_ok AND c = '4'
    WHEN 'vein_origin_thickness' THEN row_ok AND c = '4'
    ELSE true END;
  IF ok THEN RETURN NULL; END IF;
  RETURN 'its ' || pg_catalog.left(w, 40) || ' stands at row ' || pg_catalog.left(r, 20) || ' col '
         || pg_catalog.left(c, 20) || ', where no ' || pg_catalog.left(w, 40) || ' is taken';
END $$;

-- The keys an item may have; what else an event of each kind may carry beside them.
CREATE OR REPLACE FUNCTION leafdig.unknown_keys(p jsonb, allowed text[]) RETURNS text LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  RETURN (SELECT pg_catalog.string_agg(pg_catalog.left(k, 40), ', ' ORDER BY k)
            FROM pg_catalog.jsonb_object_keys(p) k WHERE k <> ALL (allowed));
END $$;

-- An event's sizes: asked before anything parses its payload.
CREATE OR REPLACE FUNCTION leafdig.size_problem(payload text, raw text) RETURNS text LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  IF pg_catalog.octet_length(payload) > 65536 THEN
    RETURN 'its payload is ' || pg_catalog.octet_length(payload) || ' bytes: at most 65536 are taken';
  END IF;
  IF pg_catalog.octet_length(raw) > 262144 THEN
    RETURN 'its raw text is ' || pg_catalog.octet_length(raw) || ' bytes: at most 262144 are taken';
  END IF;
  RETURN NULL;
END $$;

-- What is wrong with an event given the session it joins, or NULL (after its shape, which
-- payload_problem checks first): sizes and numbers, keys,
-- the item an undo, retake or correction names, and who signs a review. The events before
-- `seq` (this statement's included: an AFTER trigger sees them) are the session's.
CREATE OR REPLACE FUNCTION leafdig.event_state_problem(session_id bigint, seq bigint, kind text, payload text, raw text,
                                            writer name) RETURNS text LANGUAGE plpgsql STABLE
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  p jsonb;
  named jsonb;
  named_kind text;
  item_keys constant text[] := ARRAY['what', 'row', 'col', 'position_mm', 'value_mm', 'flag', 'frame'];
  extra text;
  holder bigint;
  key text;
BEGIN
  BEGIN
    p := payload::jsonb;
  EXCEPTION WHEN others THEN
    RETURN NULL;  -- payload_problem names it
  END;
  IF NOT leafdig.numbers_in_range(p) THEN
    RETURN 'its payload holds a number beyond ±1e15';
  END IF;
  IF pg_catalog.jsonb_typeof(p) <> 'object' THEN RETURN NULL; END IF;
  IF kind IN ('accepted', 'retake_cancelled') THEN
    extra := leafdig.unknown_keys(p, item_keys);
  ELSIF kind IN ('undone', 'retake') THEN
    extra := leafdig.unknown_keys(p, item_keys || ARRAY['seq']);
  ELSIF kind = 'corrected' THEN
    extra := coalesce(leafdig.unknown_keys(p, item_keys || ARRAY['seq', 'corrected', 'reason', 'who']),
                      CASE WHEN pg_catalog.jsonb_typeof(p -> 'corrected') = 'object'
                           THEN leafdig.unknown_keys(p -> 'corrected', item_keys) END);
  ELSIF kind = 'status' THEN
    extra := leafdig.unknown_keys(p, ARRAY['status', 'who', 'why']);
  END IF;
  IF extra IS NOT NULL THEN
    RETURN 'its payload has keys leafdig does not write (' || extra || ')';
  END IF;
  IF kind IN ('accepted', 'retake_cancelled', 'undone', 'retake', 'corrected')
     AND (pg_catalog.jsonb_path_exists(p, 'lax $.position_mm[*] ? (@ > 10000 || @ < -10000)')
          OR pg_catalog.jsonb_path_exists(p, 'lax $.value_mm ? (@ > 100)')
          OR pg_catalog.jsonb_path_exists(p, 'lax $.corrected.position_mm[*] ? (@ > 10000 || @ < -10000)')
          OR pg_catalog.jsonb_path_exists(p, 'lax $.corrected.value_mm ? (@ > 100)')) THEN
    RETURN 'its item lies beyond ±10000 mm or reads more than 100 mm';
  END IF;
  IF kind IN ('accepted', 'retake_cancelled', 'undone', 'retake', 'corrected') THEN
    extra := coalesce(leafdig.leaf_place_problem(p),
                      CASE WHEN kind = 'corrected' AND pg_catalog.jsonb_typeof(p -> 'corrected') = 'object'
                           THEN leafdig.leaf_place_problem(p -> 'corrected') END);
    IF extra IS NOT NULL THEN RETURN extra; END IF;
  END IF;
  IF kind IN ('undone', 'retake', 'corrected') AND pg_catalog.jsonb_typeof(p -> 'seq') = 'number'
     AND (p ->> 'seq') ~ '^[0-9]{1,18}$' THEN
    SELECT n.kind, CASE WHEN n.kind = 'corrected' THEN n.payload_json::jsonb -> 'corrected' ELSE n.payload_json::jsonb END
      INTO named_kind, named
      FROM leafdig.events n WHERE n.session_id = event_state_problem.session_id AND n.seq = (p ->> 'seq')::bigint;
    IF named_kind IN ('accepted', 'retake_cancelled', 'corrected') THEN
      key := leafdig.item_key(named);
      IF leafdig.item_key(p) <> key OR (kind = 'corrected' AND leafdig.item_key(p -> 'corrected') <> key) THEN
        RETURN 'it names event ' || (p ->> 'seq') || ', whose item is ' || pg_catalog.left(key, 80)
               || ', but carries another (what, row, col)';
      END IF;
      SELECT h.seq INTO holder FROM leafdig.events h
       WHERE h.session_id = event_state_problem.session_id AND h.seq < event_state_problem.seq
         AND h.kind IN ('accepted', 'retake_cancelled', 'corrected', 'undone', 'retake')
         AND leafdig.event_item_key(h.kind, h.payload_json) = key
       ORDER BY h.seq DESC LIMIT 1;
      IF holder IS DISTINCT FROM (p ->> 'seq')::bigint THEN
        RETURN 'the item event ' || (p ->> 'seq') || ' put in is no longer there (event '
               || coalesce(holder::text, '(none)') || ' took it out or replaced it)';
      END IF;
    END IF;
  END IF;
  IF leafdig.is_review_event(kind, payload) THEN
    IF p ->> 'who' IS DISTINCT FROM writer::text
       AND EXISTS (SELECT 1 FROM pg_catalog.pg_roles r WHERE r.rolname = p ->> 'who') THEN
      RETURN 'it is signed by the login ' || pg_catalog.left(p ->> 'who', 64) || ' but written by the login '
             || writer || ': a review is signed by the login that writes it (its who may be a display name, never another login)';
    END IF;
    IF EXISTS (SELECT 1 FROM leafdig.station_logins l JOIN leafdig.sessions x ON x.station = l.station
                WHERE l.login = writer AND x.id = event_state_problem.session_id)
       AND pg_catalog.pg_has_role(writer, 'leafdig_technicians', 'MEMBER') THEN
      RETURN 'the login ' || writer || ' is the technician of the station that captured it: nobody reviews their own capture';
    END IF;
  END IF;
  RETURN NULL;
END $$;

-- A session's settings: a JSON object of at most 4 MiB, every number within ±1e15.
CREATE OR REPLACE FUNCTION leafdig.session_settings_hold() RETURNS trigger LANGUAGE plpgsql
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  p jsonb;
BEGIN
  IF pg_catalog.octet_length(NEW.settings_json) > 4194304 THEN
    RAISE EXCEPTION 'session %:% refused: its settings are % bytes, at most 4194304 are taken', NEW.station,
      NEW.station_session_id, pg_catalog.octet_length(NEW.settings_json) USING ERRCODE = '22023';
  END IF;
  BEGIN
    p := NEW.settings_json::jsonb;
  EXCEPTION WHEN others THEN
    RAISE EXCEPTION 'session %:% refused: its settings are not JSON', NEW.station, NEW.station_session_id
      USING ERRCODE = '22023';
  END;
  IF pg_catalog.jsonb_typeof(p) <> 'object' OR NOT leafdig.numbers_in_range(p) THEN
    RAISE EXCEPTION 'session %:% refused: its settings are not a JSON object with every number within ±1e15',
      NEW.station, NEW.station_session_id USING ERRCODE = '22023';
  END IF;
  RETURN NEW;
END $$;
DROP TRIGGER IF EXISTS session_settings_hold ON leafdig.sessions;
CREATE TRIGGER session_settings_hold BEFORE INSERT ON leafdig.sessions
  FOR EACH ROW EXECUTE FUNCTION leafdig.session_settings_hold();

-- A session's genesis covers its station and kind (form 2: what stations of station schema 3
-- write), each field with its length; sessions of form 1 (written before) still arrive and
-- are shown as such. Version 3's check of a new session, with the form.
ALTER TABLE leafdig.sessions ADD COLUMN IF NOT EXISTS genesis_form integer NOT NULL DEFAULT 1
  CHECK (genesis_form IN (1, 2));
GRANT INSERT (genesis_form) ON leafdig.sessions TO leafdig_technicians;
CREATE OR REPLACE FUNCTION leafdig.genesis_of(form integer, station text, kind text, station_session bigint,
                                              created text, settings text) RETURNS text LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  IF form = 2 THEN
    RETURN pg_catalog.encode(pg_catalog.sha256(pg_catalog.convert_to(
      'leafdig session/2' || E'\n' || pg_catalog.octet_length(station) || ':' || station || E'\n'
      || pg_catalog.octet_length(kind) || ':' || kind || E'\n'
      || pg_catalog.octet_length(station_session::text) || ':' || station_session || E'\n'
      || pg_catalog.octet_length(created) || ':' || created || E'\n'
      || pg_catalog.octet_length(settings) || ':' || settings || E'\n', 'UTF8')), 'hex');
  END IF;
  RETURN pg_catalog.encode(pg_catalog.sha256(pg_catalog.convert_to(
    'leafdig session ' || station_session || ' ' || created || ' ' || settings, 'UTF8')), 'hex');
END $$;
CREATE OR REPLACE FUNCTION leafdig.session_arrives() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  bound text := leafdig.login_station(session_user);
BEGIN
  IF NOT leafdig.is_admin(session_user) THEN
    IF NOT pg_catalog.pg_has_role(session_user, 'leafdig_technicians', 'MEMBER') THEN
      RAISE EXCEPTION 'the login % may not push sessions: only a station''s technician pushes them', session_user
        USING ERRCODE = '42501', HINT = 'push with the technician login of the station (leafdig server add-user --role technician)';
    END IF;
    IF bound IS DISTINCT FROM NEW.station THEN
      RAISE EXCEPTION 'the login % pushes for station %, not for station % (session %:%)', session_user,
        coalesce(bound, '(none)'), NEW.station, NEW.station, NEW.station_session_id
        USING ERRCODE = '42501', HINT = 'push a station''s file with that station''s login';
    END IF;
  END IF;
  IF NEW.genesis_hash IS DISTINCT FROM leafdig.genesis_of(NEW.genesis_form, NEW.station, NEW.kind,
                                                          NEW.station_session_id, NEW.created_utc, NEW.settings_json) THEN
    RAISE EXCEPTION 'session %:% does not hash to its genesis hash (its station, kind, creation time or settings were changed)',
      NEW.station, NEW.station_session_id USING ERRCODE = 'LD002';
  END IF;
  NEW.status := 'open';
  NEW.head_seq := 0;
  NEW.head_hash := NEW.genesis_hash;
  NEW.pushed_by := session_user;
  NEW.first_pushed := pg_catalog.now();
  RETURN NEW;
END $$;

-- Version 9's statement check with the state of the session asked too.
CREATE OR REPLACE FUNCTION leafdig.events_arrived() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  admin boolean := leafdig.is_admin(session_user);
  curator boolean := pg_catalog.pg_has_role(session_user, 'leafdig_curators', 'MEMBER');
  technician boolean := pg_catalog.pg_has_role(session_user, 'leafdig_technicians', 'MEMBER');
  bound text := leafdig.login_station(session_user);
  s leafdig.sessions;
  e record;
  last_seq bigint;
  last_hash text;
  state text;
  new_status text;
  capturer boolean;
BEGIN
  FOR s IN SELECT x.* FROM leafdig.sessions x WHERE x.id IN (SELECT a.session_id FROM arrived a)
            ORDER BY x.id FOR UPDATE LOOP
    capturer := technician AND bound IS NOT DISTINCT FROM s.station;
    last_seq := s.head_seq;
    last_hash := s.head_hash;
    state := s.status;
    FOR e IN SELECT a.seq, a.station, a.utc, a.mono_ns, a.kind, a.payload_json, a.raw, a.prev_hash, a.hash,
                    leafdig.is_review_event(a.kind, a.payload_json) AS review,
                    coalesce(leafdig.size_problem(a.payload_json, a.raw),
                      leafdig.payload_problem(a.kind, a.payload_json, a.seq,
                        CASE WHEN a.kind IN ('undone', 'retake', 'corrected')
                             THEN (SELECT n.kind FROM leafdig.events n
                                    WHERE n.session_id = s.id AND n.seq = leafdig.named_seq(a.payload_json)) END,
                        s.kind),
                      leafdig.event_state_problem(s.id, a.seq, a.kind, a.payload_json, a.raw, session_user)) AS problem
               FROM arrived a WHERE a.session_id = s.id ORDER BY a.seq LOOP
      IF NOT (capturer AND NOT e.review AND state = 'open' AND e.station = s.station) THEN
        PERFORM leafdig.refuse_arrival(s.id, s, e.station, e.seq, e.review, state, admin, curator, technician, bound);
      END IF;
      new_status := NULL;
      IF e.problem IS NULL AND e.kind = 'status' THEN
        new_status := e.payload_json::jsonb ->> 'status';
        IF NOT e.review AND new_status NOT IN ('complete', 'abandoned') THEN
          e.problem := 'a capture ends as complete or abandoned, not ' || new_status;
        END IF;
      END IF;
      IF e.problem IS NOT NULL THEN
        RAISE EXCEPTION 'session %:% event % (%) refused: %', s.station, s.station_session_id, e.seq,
          pg_catalog.left(e.kind, 40), e.problem
          USING ERRCODE = '22023', HINT = 'only what leafdig writes is taken (docs/schema.md, "Event kinds")';
      END IF;
      IF e.seq <> last_seq + 1 THEN
        RAISE EXCEPTION 'session %:% event % does not follow: the server holds events 1 to %', s.station,
          s.station_session_id, e.seq, last_seq USING ERRCODE = 'LD001';
      END IF;
      IF e.prev_hash IS DISTINCT FROM last_hash THEN
        RAISE EXCEPTION 'session %:% event % does not follow the server''s event % (another previous hash): the station''s copy and the server''s differ',
          s.station, s.station_session_id, e.seq, last_seq USING ERRCODE = 'LD001';
      END IF;
      IF e.hash IS DISTINCT FROM leafdig.chain_hash(e.prev_hash, s.station_session_id, e.seq, e.utc, e.mono_ns, e.kind,
                                                    e.payload_json, e.raw) THEN
        RAISE EXCEPTION 'session %:% event % does not hash to its hash: it was changed after it was written',
          s.station, s.station_session_id, e.seq USING ERRCODE = 'LD002';
      END IF;
      last_seq := e.seq;
      last_hash := e.hash;
      state := coalesce(new_status, state);
    END LOOP;
    UPDATE leafdig.sessions x SET head_seq = last_seq, head_hash = last_hash, status = state
     WHERE x.id = s.id;
  END LOOP;
  RETURN NULL;
END $$;
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
)SQL",
    // ---- version 11: a review names the login that writes it (docs/server-schema.md) --------
    R"SQL(
-- A decision or correction is signed by the login writing it: its `who` is that login, or
-- "NAME (login)" (leafdig adds the login to a name given with --who). Whoever reads it later —
-- on the server, in a station's file after a pull, in an export — sees the login that wrote
-- it, not only a display name. Reviews written before stay as they are.
CREATE OR REPLACE FUNCTION leafdig.review_signed() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  writer text := session_user;
  tail text := ' (' || session_user || ')';
  who text;
BEGIN
  IF NOT leafdig.is_review_event(NEW.kind, NEW.payload_json) THEN RETURN NEW; END IF;
  BEGIN
    who := NEW.payload_json::jsonb ->> 'who';
  EXCEPTION WHEN others THEN
    RETURN NEW;  -- not JSON: the statement's check names it (as it names a review with no who)
  END;
  IF who IS NULL OR who = writer OR (pg_catalog.length(who) > pg_catalog.length(tail)
                      AND pg_catalog.right(who, pg_catalog.length(tail)) = tail) THEN
    RETURN NEW;
  END IF;
  RAISE EXCEPTION 'event % of session % refused: it is signed "%" but written by the login %: a review is signed by the login that writes it ("%", or "NAME (%)")',
    NEW.seq, NEW.session_id, pg_catalog.left(coalesce(who, '(nobody)'), 80), writer, writer, writer
    USING ERRCODE = '42501', HINT = 'leave out --who, or give your name: leafdig adds the login';
END $$;
DROP TRIGGER IF EXISTS review_signed ON leafdig.events;
-- Checked when the transaction commits: row-level security and every check of the statement
-- (roles, a final decision, the payload) speak first.
CREATE CONSTRAINT TRIGGER review_signed AFTER INSERT ON leafdig.events DEFERRABLE INITIALLY DEFERRED
  FOR EACH ROW WHEN (NEW.kind IN ('status', 'corrected')) EXECUTE FUNCTION leafdig.review_signed();
REVOKE ALL ON ALL FUNCTIONS IN SCHEMA leafdig FROM PUBLIC;
GRANT EXECUTE ON ALL FUNCTIONS IN SCHEMA leafdig TO leafdig_technicians, leafdig_curators, leafdig_readers;
)SQL",
};

}  // namespace leafdig::db::detail
