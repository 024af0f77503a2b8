
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
