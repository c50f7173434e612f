"""Latin hypercube points: runs counted as independent draws, a conservative reading."""
from designs.base import stratified_runs_meaning


def counted_runs_meaning(f):
    return stratified_runs_meaning("latin_hypercube")
