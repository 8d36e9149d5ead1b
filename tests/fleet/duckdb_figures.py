"""The figures of `btx fleet` computed by DuckDB from its Parquet export.

Usage: duckdb_figures.py EXPORT_DIR; prints them as JSON.
"""
import json
import sys

import duckdb

root = sys.argv[1]
db = duckdb.connect()
db.execute(f"create view runs as select * from read_parquet('{root}/runs/**/*.parquet', hive_partitioning = true)")
db.execute(f"create view nodes as select * from read_parquet('{root}/nodes/**/*.parquet', hive_partitioning = true)")
db.execute(f"create view transitions as select * from read_parquet('{root}/transitions/**/*.parquet', hive_partitioning = true)")

out = {
    "runs": db.sql("select count(*) from runs").fetchall()[0][0],
    "outcomes": dict(db.sql("select coalesce(outcome, 'unfinished'), count(*) from runs group by all").fetchall()),
    "transitions": db.sql("select count(*) from transitions").fetchall()[0][0],
    "robots": db.sql("select count(distinct robot) from transitions").fetchall()[0][0],
    "nodes": {
        str(uid): {"ran_in": ran, "failed_in": failed, "failures": int(f), "recovered": int(rec), "unrecovered": int(unrec)}
        for uid, ran, failed, f, rec, unrec in db.sql(
            "select uid, count(*), count(*) filter (where failures > 0), sum(failures), sum(recovered), sum(unrecovered) from nodes group by uid"
        ).fetchall()
    },
    # The same failures counted from the transitions themselves.
    "failed_in_from_transitions": {
        str(uid): n
        for uid, n in db.sql("select uid, count(distinct run) from transitions where status = 'FAILURE' group by uid").fetchall()
    },
    # Every row of each .btlog run (its ticks, steps and times are
    # bit-packed differences in the export), in order.
    "log_rows": {
        run: {"numbers": rows, "texts": texts}
        for run, rows, texts in db.sql(
            "select run, list([tick, step, uid, time_us] order by tick, step), list([node, prev, status] order by tick, step) from transitions where run like '%.btlog' group by run"
        ).fetchall()
    },
    "causes": dict(db.sql("select what_went_wrong, count(*) from runs where outcome = 'FAILURE' group by all").fetchall()),
}
print(json.dumps(out))
