//! `syn`-based parser for the scheme language (grammar in [`super`]).

use super::ast::*;
use proc_macro2::TokenStream;
use syn::parse::{Parse, ParseStream};
use syn::{braced, Attribute, Expr, Ident, Token};

/// Parse a scheme from a token stream (the proc-macro path).
pub fn parse_tokens(tokens: TokenStream) -> syn::Result<SchemeAst> {
    syn::parse2::<SchemeAst>(tokens)
}

/// Parse a scheme from source text (the build-time/CLI path).
/// Errors carry line/column through `proc_macro2`'s span locations.
pub fn parse_str(text: &str) -> syn::Result<SchemeAst> {
    let tokens: TokenStream = text.parse().map_err(|e: proc_macro2::LexError| {
        syn::Error::new(e.span(), format!("cannot tokenize scheme source: {e}"))
    })?;
    parse_tokens(tokens)
}

fn kw(input: ParseStream, word: &str) -> syn::Result<Ident> {
    let id: Ident = input.call(<Ident as syn::ext::IdentExt>::parse_any)?;
    if id != word {
        return Err(syn::Error::new(
            id.span(),
            format!("expected `{word}`, found `{id}`"),
        ));
    }
    Ok(id)
}

fn peek_kw(input: ParseStream, word: &str) -> bool {
    let fork = input.fork();
    matches!(fork.call(<Ident as syn::ext::IdentExt>::parse_any), Ok(id) if id == word)
}

fn doc_of(attrs: &[Attribute]) -> String {
    let mut lines = Vec::new();
    for a in attrs {
        if a.path().is_ident("doc") {
            if let syn::Meta::NameValue(nv) = &a.meta {
                if let Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Str(s),
                    ..
                }) = &nv.value
                {
                    lines.push(s.value().trim().to_string());
                }
            }
        }
    }
    lines.join("\n")
}

impl Parse for SchemeAst {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        kw(input, "scheme")?;
        let name: Ident = input.parse()?;
        let body;
        braced!(body in input);
        let mut facet = None;
        let mut consts = Vec::new();
        let mut vertex = None;
        let mut sectors = Vec::new();
        let mut patches = Vec::new();
        while !body.is_empty() {
            let _inner_attrs = body.call(Attribute::parse_outer)?;
            if peek_kw(&body, "facet") {
                let k = kw(&body, "facet")?;
                if facet.is_some() {
                    return Err(syn::Error::new(k.span(), "`facet` given twice"));
                }
                facet = Some(body.parse::<Ident>()?);
                body.parse::<Token![;]>()?;
            } else if body.peek(Token![const]) {
                body.parse::<Token![const]>()?;
                let name: Ident = body.parse()?;
                body.parse::<Token![=]>()?;
                let expr: Expr = body.parse()?;
                body.parse::<Token![;]>()?;
                consts.push(ConstAst { name, expr });
            } else if peek_kw(&body, "vertex") {
                let k = kw(&body, "vertex")?;
                if vertex.is_some() {
                    return Err(syn::Error::new(k.span(), "`vertex` block given twice"));
                }
                let inner;
                braced!(inner in body);
                vertex = Some(parse_defs(&inner, Block::Vertex)?);
            } else if peek_kw(&body, "sector") {
                kw(&body, "sector")?;
                let kind: Ident = body.parse()?;
                let inner;
                braced!(inner in body);
                let defs = parse_defs(&inner, Block::Sector)?;
                sectors.push(SectorAst { kind, defs });
            } else if peek_kw(&body, "patch") {
                kw(&body, "patch")?;
                let class: Ident = body.parse()?;
                body.parse::<Token![:]>()?;
                let form: Ident = body.parse()?;
                let inner;
                braced!(inner in body);
                let defs = parse_defs(&inner, Block::Patch)?;
                patches.push(PatchAst { class, form, defs });
            } else {
                return Err(body.error("expected `facet`, `const`, `vertex`, `sector` or `patch`"));
            }
        }
        let facet = facet.ok_or_else(|| syn::Error::new(name.span(), "missing `facet quad;`"))?;
        // Triangle schemes (pn.md) read only their corners' positions and
        // normals: they have no vertex stage.
        let vertex = match (vertex, facet == "tri") {
            (Some(v), false) => v,
            (None, true) => Vec::new(),
            (None, false) => {
                return Err(syn::Error::new(name.span(), "missing `vertex { … }` block"))
            }
            (Some(_), true) => {
                return Err(syn::Error::new(
                    facet.span(),
                    "a `facet tri` scheme has no `vertex` block: its patches read the corners' positions `P(i)` and normals `N(i)`",
                ))
            }
        };
        if patches.is_empty() {
            return Err(syn::Error::new(
                name.span(),
                "a scheme needs at least one `patch` block",
            ));
        }
        Ok(SchemeAst {
            name,
            doc: doc_of(&attrs),
            facet,
            consts,
            vertex,
            sectors,
            patches,
        })
    }
}

/// Which block definitions are parsed for (each admits its own keywords).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Block {
    Vertex,
    Sector,
    Patch,
}

fn parse_defs(input: ParseStream, block: Block) -> syn::Result<Vec<DefAst>> {
    let patch = block == Block::Patch;
    let mut defs = Vec::new();
    while !input.is_empty() {
        let start = input.span();
        let kind = if block == Block::Sector {
            if peek_kw(input, "sharp") {
                kw(input, "sharp")?;
                DefKind::Sharp
            } else if input.peek(Token![let]) {
                // A block-local helper (resolve.rs: `sector_block`).
                input.parse::<Token![let]>()?;
                DefKind::Let
            } else if peek_kw(input, "out") || peek_kw(input, "vector") {
                return Err(input.error(
                    "a `sector` block overrides vertex definitions: write `NAME = …` or `sharp NAME[j] = …` (or `let NAME = …` for a local helper)",
                ));
            } else {
                DefKind::Point
            }
        } else if input.peek(Token![let]) {
            input.parse::<Token![let]>()?;
            DefKind::Let
        } else if peek_kw(input, "out") {
            let k = kw(input, "out")?;
            if !patch {
                return Err(syn::Error::new(
                    k.span(),
                    "`out` is only valid in a `patch` block",
                ));
            }
            DefKind::Out
        } else if peek_kw(input, "vector") {
            let k = kw(input, "vector")?;
            if patch {
                return Err(syn::Error::new(
                    k.span(),
                    "`vector` marks vertex-stage outputs; patch locals are typed by use",
                ));
            }
            DefKind::Vector
        } else {
            DefKind::Point
        };
        let name: Ident = input.parse()?;
        let index = if input.peek(syn::token::Bracket) {
            let inner;
            syn::bracketed!(inner in input);
            let idx: Ident = inner.parse()?;
            if !inner.is_empty() {
                return Err(inner.error("a definition is indexed by one plain name, e.g. `e[j]`"));
            }
            Some(idx)
        } else {
            None
        };
        input.parse::<Token![=]>()?;
        let expr: Expr = input.parse()?;
        input.parse::<Token![;]>()?;
        defs.push(DefAst {
            kind,
            name,
            index,
            expr,
            span: start,
        });
    }
    Ok(defs)
}
