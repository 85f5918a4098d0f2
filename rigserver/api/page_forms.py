"""What every page form shares: reading a page needs a session where reads are not public
(:class:`LoginFirst`), a form is posted from this origin with the session's form token, and
its writer is the session's key with the stand's write scope."""

from __future__ import annotations

from collections.abc import Sequence
from urllib.parse import parse_qs, urlsplit

from fastapi import Request

from rigserver.api.auth import READ, ApiKey, write_scope
from rigserver.api.deps import Services, ServicesDep, caller_of, require_scope
from rigserver.api.problems import ApiProblem
from rigserver.api.sessions import COOKIE
from schemas.stands import StandKind


class LoginFirst(Exception):
    """A page asked for without a key or session: answered with the login page's address."""

    def __init__(self, next_page: str) -> None:
        self.next_page = next_page


async def require_page_read(request: Request, services: ServicesDep) -> None:
    if services.settings.public_reads:
        return
    caller = caller_of(request, services)
    if caller is None:
        query = f"?{request.url.query}" if request.url.query else ""
        raise LoginFirst(request.url.path + query)
    require_scope(caller, READ)


def same_origin(request: Request) -> None:
    """403 for a form posted from another site (cross-site request forgery): a browser
    says where a post comes from (``Sec-Fetch-Site``, ``Origin``); a client that says
    neither is no browser, and no other site's page can make it post."""
    site = request.headers.get("sec-fetch-site")
    origin = request.headers.get("origin")
    if (site is not None and site not in ("same-origin", "none")) or (
        origin is not None and _host_of(origin) != request.headers.get("host")
    ):
        raise ApiProblem(
            403,
            "Cross-site form refused",
            f"{request.url.path} takes forms of this site's own pages only "
            f"(Origin {origin!r:.60}, Sec-Fetch-Site {site!r:.30})",
        )


def _host_of(origin: str) -> str | None:
    """The host (and port) of an ``Origin`` header; None for ``null`` or nonsense."""
    try:
        return urlsplit(origin).netloc or None
    except ValueError:
        return None


def writable_stands(writer: ApiKey | None) -> list[StandKind]:
    """The stands whose runs ``writer`` may open and type into."""
    if writer is None:
        return []
    return [kind for kind in StandKind if writer.allows(write_scope(kind.value))]


def read_form(body: bytes, known: Sequence[str]) -> dict[str, str]:
    """The fields of a form's body (URL-encoded UTF-8), the last value of each; 422 for a
    body that is none or a field not ``known``."""
    try:
        form = parse_qs(
            body.decode("ascii"),
            keep_blank_values=True,
            strict_parsing=bool(body),
            encoding="utf-8",
            errors="strict",
            max_num_fields=len(known),
        )
    except ValueError as exc:  # UnicodeDecodeError too
        raise ApiProblem(
            422, "Invalid form", f"the form is not URL-encoded UTF-8 with its fields: {exc}"
        ) from None
    unknown = sorted(set(form) - set(known))
    if unknown:
        raise ApiProblem(422, "Invalid form", f"unknown field {unknown[0][:40]!r}")
    return {name: values[-1] for name, values in form.items()}


def form_writer(request: Request, services: Services, given: str, back: str) -> ApiKey:
    """The key a page's form writes with: of the request's Authorization header (no
    browser's cookie: nothing to forge), else of its session, whose form token ``given``
    must be (403 else: a form of another site); without either, the login page, then
    ``back``. The form is this site's (:func:`same_origin`)."""
    same_origin(request)
    token = request.cookies.get(COOKIE)
    if request.headers.get("authorization") or token is None:
        caller = caller_of(request, services)
        if caller is None:
            raise LoginFirst(back)
        return caller
    key = services.sessions.key(token)
    if key is None:
        raise LoginFirst(back)
    if not services.sessions.form_token_holds(token, given):
        raise ApiProblem(
            403,
            "Form token missing",
            "the form does not carry this session's token: a form of this site's pages "
            "only (reload the page)",
        )
    return key


#: The field of every page form that carries the session's form token.
FORM_TOKEN = "form_token"


def writer_of(request: Request, services: Services) -> ApiKey | None:
    """The key of the request's Authorization header, else of its session, all its scopes
    (only this site's pages and forms are answered with it)."""
    caller = caller_of(request, services)
    token = request.cookies.get(COOKIE)
    if request.headers.get("authorization") or token is None:
        return caller
    return services.sessions.key(token)


def form_token(request: Request, services: Services) -> str:
    """The form token of the request's session ("" without one)."""
    token = request.cookies.get(COOKIE)
    return (services.sessions.form_token(token) or "") if token else ""


def signed_in(request: Request, services: Services) -> bool:
    """Whether the browser holds a live session (a cookie left from an expired session or
    from before a restart is none: no log-out button for it)."""
    token = request.cookies.get(COOKIE)
    return token is not None and services.sessions.find(token) is not None
