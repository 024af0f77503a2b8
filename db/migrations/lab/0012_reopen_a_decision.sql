-- A curator reopens an approved or rejected session, saying why (issue 49): a `status` event
-- back to `complete` that names the decision it reopens, {"status": "complete", "who", "why",
-- "reopens": "approved" | "rejected"}. It is a review event (signed by its login, never a
-- technician's, never one's own capture), it follows only the decision it names, and after it
-- the session is complete again: corrections and a new decision may follow, capture events may
-- not (docs/lab.md, "Review").

-- What a reopening reopens (its "reopens"), or NULL for any other event.
CREATE OR REPLACE FUNCTION leafdig.reopened_decision(kind text, payload text) RETURNS text LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  p jsonb;
BEGIN
  IF kind IS DISTINCT FROM 'status' THEN RETURN NULL; END IF;
  BEGIN
    p := payload::jsonb;
  EXCEPTION WHEN others THEN
    RETURN NULL;  -- not JSON: the statement's check names it
  END;
  IF pg_catalog.jsonb_typeof(p) <> 'object' OR NOT p ? 'reopens' THEN RETURN NULL; END IF;
  RETURN coalesce(p ->> 'reopens', '(not text)');
END $$;

-- A curator's event: a correction, a decision (approved or rejected), or a reopening.
CREATE OR REPLACE FUNCTION leafdig.is_review_event(kind text, payload text) RETURNS boolean LANGUAGE plpgsql IMMUTABLE
  SET search_path = pg_catalog, pg_temp AS $$
BEGIN
  IF kind = 'corrected' THEN RETURN true; END IF;
  IF kind IS DISTINCT FROM 'status' THEN RETURN false; END IF;
  BEGIN
    RETURN coalesce((payload::jsonb ->> 'status') IN ('approved', 'rejected'), false)
           OR leafdig.reopened_decision(kind, payload) IS NOT NULL;
  EXCEPTION WHEN others THEN
    RETURN false;  -- not JSON: not a review event (the arrival check refuses it by name)
  END;
END $$;

-- Version 10's checks of an event in its session, with a reopening's shape.
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
    extra := leafdig.unknown_keys(p, ARRAY['status', 'who', 'why', 'reopens']);
    IF extra IS NULL AND p ? 'reopens' AND NOT (p ->> 'status' = 'complete'
         AND coalesce(pg_catalog.jsonb_typeof(p -> 'reopens'), '') = 'string' AND p ->> 'reopens' IN ('approved', 'rejected')
         AND coalesce(pg_catalog.jsonb_typeof(p -> 'who'), '') = 'string'
         AND coalesce(pg_catalog.jsonb_typeof(p -> 'why'), '') = 'string' AND pg_catalog.btrim(p ->> 'why') <> '') THEN
      RETURN 'a reopening sets the status complete, names the decision it reopens (approved or rejected) and says who and why';
    END IF;
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

-- Version 9's check of each row, a curator's event on a decided session left to the statement's.
CREATE OR REPLACE FUNCTION leafdig.event_arrives() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
  SET search_path = pg_catalog, pg_temp AS $$
DECLARE
  s leafdig.sessions;
  review boolean;
BEGIN
  SELECT x.* INTO s FROM leafdig.sessions x WHERE x.id = NEW.session_id;
  -- The station's technician adding a capture event to its open session passes every rule of
  -- refuse_arrival; anything else is asked in full.
  IF NOT (FOUND AND NEW.station = s.station AND s.status = 'open' AND NEW.kind NOT IN ('corrected', 'status')
          AND pg_catalog.pg_has_role(session_user, 'leafdig_technicians', 'MEMBER')
          AND leafdig.login_station(session_user) = s.station) THEN
    review := leafdig.is_review_event(NEW.kind, NEW.payload_json);
    -- A curator's event on a decided session may follow a reopening in the same statement: the
    -- statement's check (events_arrived) asks the state as each event finds it.
    PERFORM leafdig.refuse_arrival(NEW.session_id, s, NEW.station, NEW.seq, review,
                                   CASE WHEN review AND s.status IN ('approved', 'rejected') THEN 'complete'
                                        ELSE s.status END,
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

-- Version 10's statement check, a reopening asked as what it is.
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
  reopens text;
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
      reopens := leafdig.reopened_decision(e.kind, e.payload_json);
      IF NOT (capturer AND NOT e.review AND state = 'open' AND e.station = s.station) THEN
        -- A reopening is the one event that follows a decision: asked as a review of a complete session.
        PERFORM leafdig.refuse_arrival(s.id, s, e.station, e.seq, e.review,
                                       CASE WHEN reopens IS NOT NULL AND state IN ('approved', 'rejected')
                                            THEN 'complete' ELSE state END,
                                       admin, curator, technician, bound);
      END IF;
      IF e.problem IS NULL AND reopens IS NOT NULL AND reopens IS DISTINCT FROM state THEN
        e.problem := 'it reopens a session ' || pg_catalog.left(reopens, 20) || ' but the session is ' || state
                     || ': only an approved or rejected session is reopened, naming its decision';
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
