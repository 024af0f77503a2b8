
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
