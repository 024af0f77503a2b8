
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
