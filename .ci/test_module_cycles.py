#!/usr/bin/env python3
"""Tests of `.ci/module-cycles`: one small crate per kind of import edge, written to a temporary
folder, and the repository itself, which must have no circle. Run with
`python3 .ci/test_module_cycles.py`."""
import contextlib
import importlib.machinery
import importlib.util
import io
import os
import tempfile
import textwrap
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))


def load_script():
    path = os.path.join(HERE, "module-cycles")
    loader = importlib.machinery.SourceFileLoader("module_cycles", path)
    spec = importlib.util.spec_from_loader("module_cycles", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


mc = load_script()


class Crate:
    """A crate in a temporary folder: `files` maps a path under `src/` to its text."""

    def __init__(self, files, name="demo"):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = os.path.join(self.tmp.name, "crates")
        self.dir = os.path.join(self.root, name)
        for rel, text in files.items():
            path = os.path.join(self.dir, "src", rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8") as f:
                f.write(textwrap.dedent(text))

    def circles(self):
        """Each circle as the sorted list of its modules."""
        return [comp for _, comp, _ in mc.check(self.dir)]

    def main(self, allowed):
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = mc.main(self.root, allowed)
        return code, out.getvalue() + err.getvalue()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.tmp.cleanup()


# A child that uses an item of its parent: half of a circle when the parent uses the child.
CHILD_USES_PARENT = """
    use super::Shared;
    pub struct Item;
    pub fn make() -> Shared { Shared }
"""


class ParentAndChild(unittest.TestCase):
    def parent(self, body):
        return {
            "lib.rs": "pub mod a;\n",
            "a/mod.rs": "mod child;\npub struct Shared;\n" + textwrap.dedent(body),
            "a/child.rs": CHILD_USES_PARENT,
        }

    def test_a_mod_declaration_is_not_an_import(self):
        with Crate(self.parent("")) as crate:
            self.assertEqual(crate.circles(), [])

    def test_a_pure_re_export_is_not_an_import(self):
        with Crate(self.parent("pub use child::Item;\npub(crate) use self::child::make;\n")) as c:
            self.assertEqual(c.circles(), [])

    def test_a_re_export_the_parent_uses_is_an_import(self):
        body = "pub use child::Item;\npub fn twice() -> [Item; 2] { [Item, Item] }\n"
        with Crate(self.parent(body)) as crate:
            self.assertEqual(crate.circles(), [["a", "a::child"]])

    def test_a_private_use_of_the_child_is_an_import(self):
        with Crate(self.parent("use child::Item;\n")) as crate:
            self.assertEqual(crate.circles(), [["a", "a::child"]])

    def test_a_child_path_in_code_is_an_import(self):
        with Crate(self.parent("pub fn f() { let _ = child::make(); }\n")) as crate:
            self.assertEqual(crate.circles(), [["a", "a::child"]])

    def test_a_self_path_in_code_is_an_import(self):
        with Crate(self.parent("pub fn f() { let _ = self::child::make(); }\n")) as crate:
            self.assertEqual(crate.circles(), [["a", "a::child"]])

    def test_a_crate_path_to_the_child_is_an_import(self):
        with Crate(self.parent("pub fn f() { let _ = crate::a::child::make(); }\n")) as crate:
            self.assertEqual(crate.circles(), [["a", "a::child"]])

    def test_the_crate_root_using_a_module_is_an_import(self):
        files = {
            "lib.rs": "mod a;\npub struct Root;\npub fn f() { a::g(); }\n",
            "a.rs": "pub fn g() -> crate::Root { crate::Root }\n",
        }
        with Crate(files) as crate:
            self.assertEqual(crate.circles(), [["", "a"]])


class Groups(unittest.TestCase):
    def test_a_group_under_super(self):
        files = {
            "lib.rs": "mod a;\nmod b;\nmod c;\n",
            "a.rs": "use super::{c::C, b::B};\npub struct A;\n",
            "b.rs": "pub struct B;\nuse crate::a::A;\n",
            "c.rs": "pub struct C;\n",
        }
        with Crate(files) as crate:
            self.assertEqual(crate.circles(), [["a", "b"]])

    def test_a_nested_group_under_crate(self):
        files = {
            "lib.rs": "mod a;\nmod b;\n",
            "a.rs": "use crate::{\n    b::{\n        inner::{X, Y as Z},\n    },\n};\nfn g() {}\n",
            "b/mod.rs": "pub mod inner;\n",
            "b/inner.rs": "pub struct X;\npub struct Y;\npub fn f() { crate::a::g(); }\n",
        }
        with Crate(files) as crate:
            self.assertEqual(crate.circles(), [["a", "b::inner"]])

    def test_self_in_a_group_and_an_imported_module_path(self):
        files = {
            "lib.rs": "mod a;\nmod b;\n",
            "a.rs": "use crate::b::{self};\npub struct A;\npub fn f() { b::g(); }\n",
            "b.rs": "pub fn g() {}\npub fn h() -> super::a::A { super::a::A }\n",
        }
        with Crate(files) as crate:
            self.assertEqual(crate.circles(), [["a", "b"]])

    def test_super_super(self):
        files = {
            "lib.rs": "mod a;\nmod b;\n",
            "a/mod.rs": "mod deep;\n",
            "a/deep.rs": "use super::super::b::B;\npub struct D;\n",
            "b.rs": "pub struct B;\npub fn f() -> crate::a::deep::D { todo!() }\n",
        }
        with Crate(files) as crate:
            # `crate::a::deep` is private to `a`, but the graph is about uses, not visibility.
            self.assertEqual(crate.circles(), [["a::deep", "b"]])


class Resolution(unittest.TestCase):
    def test_a_sibling_reached_through_the_parents_re_export(self):
        # `super::A` is `a`'s item, re-exported by the parent: the edge is to `a`, and the
        # parent is in no circle.
        files = {
            "lib.rs": "mod a;\nmod b;\npub use a::A;\n",
            "a.rs": "pub struct A;\nuse crate::b::B;\n",
            "b.rs": "pub struct B;\nuse super::A;\n",
        }
        with Crate(files) as crate:
            self.assertEqual(crate.circles(), [["a", "b"]])

    def test_an_item_through_an_imported_module(self):
        files = {
            "lib.rs": "mod a;\nmod setup;\n",
            "a.rs": "use crate::setup;\npub struct A;\npub fn f() { let _ = setup::Spec; }\n",
            "setup/mod.rs": "pub mod sensor;\npub use sensor::Spec;\n",
            "setup/sensor.rs": "pub struct Spec;\npub fn g() -> crate::a::A { crate::a::A }\n",
        }
        with Crate(files) as crate:
            self.assertEqual(crate.circles(), [["a", "setup::sensor"]])

    def test_an_inline_module(self):
        files = {
            "lib.rs": "mod a;\nmod b;\n",
            "a.rs": "pub mod inner {\n    pub fn f() { crate::b::g(); }\n}\n",
            "b.rs": "pub fn g() {}\npub fn h() { crate::a::inner::f(); }\n",
        }
        with Crate(files) as crate:
            self.assertEqual(crate.circles(), [["a::inner", "b"]])

    def test_a_binary_is_a_crate_of_its_own(self):
        files = {
            "lib.rs": "pub mod a;\n",
            "a.rs": "pub fn f() {}\n",
            "main.rs": "mod cli;\npub const NAME: &str = \"x\";\nfn main() { cli::run(); }\n",
            "cli.rs": "pub fn run() { let _ = crate::NAME; }\n",
        }
        with Crate(files) as crate:
            found = [(root, comp) for root, comp, _ in mc.check(crate.dir)]
            self.assertEqual(found, [("main.rs", ["", "cli"])])


class NotCode(unittest.TestCase):
    def crate(self, a_text):
        return Crate(
            {
                "lib.rs": "mod a;\nmod b;\n",
                "a.rs": a_text,
                "b.rs": "pub struct B;\nuse crate::a::A;\n",
            }
        )

    def test_comments_and_literals_are_skipped(self):
        text = r'''
            //! [`crate::b::B`] in the module docs.
            /// See [`crate::b::B`].
            pub struct A;
            // use crate::b::B;
            /* crate::b::B /* nested */ crate::b::B */
            pub const S: &str = "crate::b::B \" crate::b::B";
            pub const R: &str = r##"crate::b::B "# crate::b::B"##;
            pub const Y: &[u8] = b"crate::b::B";
            pub const C: char = '"';
            pub fn f<'a>(x: &'a str) -> &'a str { x }
        '''
        with self.crate(text) as crate:
            self.assertEqual(crate.circles(), [])

    def test_code_after_a_char_literal_and_a_lifetime_is_seen(self):
        text = r'''
            pub struct A;
            pub fn f<'a>(x: &'a str) -> char { let _ = '"'; let _ = '\''; '{' }
            pub fn g() { let _ = crate::b::B; }
        '''
        with self.crate(text) as crate:
            self.assertEqual(crate.circles(), [["a", "b"]])

    def test_test_modules_and_test_only_items_are_skipped(self):
        text = """
            pub struct A;
            #[cfg(test)]
            use crate::b::B;
            #[cfg(test)]
            #[allow(dead_code)]
            fn helper() -> crate::b::B { crate::b::B }
            #[cfg(test)]
            mod tests {
                use crate::b::B;
                mod deeper { fn f() { let _ = crate::b::B; } }
            }
            #[cfg(test)]
            mod more;
            pub fn after() {}
        """
        files = {
            "lib.rs": "mod a;\nmod b;\n",
            "a.rs": text,
            "a/more.rs": "use crate::b::B;\n",
            "b.rs": "pub struct B;\nuse crate::a::A;\n",
        }
        with Crate(files) as crate:
            self.assertEqual(crate.circles(), [])

    def test_code_after_a_test_module_is_seen(self):
        text = """
            pub struct A;
            #[cfg(test)]
            mod tests {
                use super::*;
            }
            pub fn after() { let _ = crate::b::B; }
        """
        with self.crate(text) as crate:
            self.assertEqual(crate.circles(), [["a", "b"]])


class Main(unittest.TestCase):
    FILES = {
        "lib.rs": "mod a;\nmod b;\n",
        "a.rs": "pub struct A;\nuse crate::b::B;\n",
        "b.rs": "pub struct B;\nuse crate::a::A;\n",
    }

    def test_a_circle_fails_and_names_its_edges(self):
        with Crate(self.FILES) as crate:
            code, text = crate.main({})
        self.assertEqual(code, 1)
        self.assertIn("demo (lib.rs): a <-> b", text)
        self.assertIn("a -> b: use crate::b::B;", text)

    def test_an_allowed_circle_passes_and_a_gone_one_fails(self):
        key = ("demo", "lib.rs", ("a", "b"))
        with Crate(self.FILES) as crate:
            self.assertEqual(crate.main({key: "why"})[0], 0)
        files = dict(self.FILES, **{"b.rs": "pub struct B;\n"})
        with Crate(files) as crate:
            code, text = crate.main({key: "why"})
        self.assertEqual(code, 1)
        self.assertIn("allowed but gone", text)


class Repository(unittest.TestCase):
    def test_the_repository_has_no_circle(self):
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = mc.main()
        self.assertEqual(code, 0, err.getvalue())


if __name__ == "__main__":
    unittest.main()
