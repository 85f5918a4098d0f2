"""Throwaway local PostgreSQL and HSDS servers started in a directory: for the tests, the
benchmarks and a cluster on one machine (:mod:`rigserver.cluster`); never for production."""
