
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
