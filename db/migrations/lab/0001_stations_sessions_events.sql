
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
