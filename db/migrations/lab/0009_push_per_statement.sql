
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
