"""rigserver.web: the pages (the runs list, a run's live view) with their templates and
static files. Rendered by :mod:`rigserver.web.pages` from data the API layer hands in."""
