"""docs/PYTHON_API.md is what scripts/python_api.py generates from the module's docstrings."""
import importlib.util


def test_the_api_page_matches_the_docstrings(source_dir):
    spec = importlib.util.spec_from_file_location("python_api", source_dir / "scripts" / "python_api.py")
    generator = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(generator)
    page = source_dir / "docs" / "PYTHON_API.md"
    assert page.read_text() == generator.render(), (
        "docs/PYTHON_API.md differs from the docstrings: run "
        "PYTHONPATH=build/python python3 scripts/python_api.py")
