
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
