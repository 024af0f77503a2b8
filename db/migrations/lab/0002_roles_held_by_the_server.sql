
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
