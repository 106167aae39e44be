"""The generated API overview is current and every public name is documented."""

from __future__ import annotations

import importlib.util
import re

import pytest

from tests.conftest import REPO


def _make_api():
    spec = importlib.util.spec_from_file_location("make_api", REPO / "docs" / "make_api.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


make_api = _make_api()


def _public() -> list[tuple[str, str]]:
    return [
        (module_name, name)
        for module_name, _, _ in make_api.NAMESPACES
        for name in make_api.public_names(module_name)
        if name != "__version__"
    ]


def test_api_page_is_up_to_date() -> None:
    current = (REPO / "docs" / "api.md").read_text(encoding="utf-8")
    assert current == make_api.render(), "docs/api.md is stale: run python docs/make_api.py"


def test_every_public_name_has_a_heading() -> None:
    text = (REPO / "docs" / "api.md").read_text(encoding="utf-8")
    headings = set(re.findall(r"^### `([\w.]+)`$", text, flags=re.M))
    expected = {f"{m}.{n}" for m, n in _public()}
    assert expected - headings == set()
    assert headings - expected == set()


@pytest.mark.parametrize(("module_name", "name"), _public(), ids=lambda v: v)
def test_public_name_is_documented(module_name: str, name: str) -> None:
    obj = getattr(__import__(module_name, fromlist=[name]), name)
    summary = make_api.first_paragraph(obj)
    assert len(summary) >= 10, f"{module_name}.{name} has no docstring of its own"


def test_first_paragraph_ignores_dataclass_default_doc() -> None:
    import dataclasses

    @dataclasses.dataclass(frozen=True)
    class Bare:
        x: int = 0

    @dataclasses.dataclass(frozen=True)
    class Documented:
        """One line.

        More text.
        """

        x: int = 0

    assert make_api.first_paragraph(Bare) == ""
    assert make_api.first_paragraph(Documented) == "One line."


def test_api_check_mode_detects_a_stale_page(tmp_path, monkeypatch) -> None:
    stale = tmp_path / "api.md"
    stale.write_text("# old\n", encoding="utf-8")
    monkeypatch.setattr(make_api, "API_MD", stale)
    assert make_api.main(["--check"]) == 1
    assert make_api.main([]) == 0
    assert make_api.main(["--check"]) == 0


def test_getting_started_links_resolve() -> None:
    page = REPO / "docs" / "getting-started.md"
    targets = re.findall(r"\]\(([^)#]+)\)", page.read_text(encoding="utf-8"))
    assert targets
    missing = [t for t in targets if not (page.parent / t).exists()]
    assert missing == []


def test_getting_started_uses_the_readme_commands() -> None:
    blocks = re.findall(r"```bash\n(.*?)```", (REPO / "README.md").read_text(), flags=re.S)
    page = (REPO / "docs" / "getting-started.md").read_text(encoding="utf-8")
    for block in blocks:
        assert block.strip() in page
