
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
