//! quick-xml's event reader turned into a small element tree that keeps the
//! byte span of every start tag, so later checks can point at the source.

use crate::source::Located;
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::path::Path;

#[derive(Debug, Clone)]
pub struct Attr {
    pub key: String,
    pub value: String,
}

#[derive(Debug, Clone)]
pub struct Element {
    pub tag: String,
    pub attrs: Vec<Attr>,
    pub children: Vec<Element>,
    /// Byte range of the start tag.
    pub start: usize,
    pub end: usize,
    /// Text content (only kept for port descriptions in models).
    pub text: String,
}

impl Element {
    pub fn attr(&self, key: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|a| a.key == key)
            .map(|a| a.value.as_str())
    }
}

/// The deepest nesting of elements read, as tinyxml2's
/// TINYXML2_MAX_ELEMENT_DEPTH (BehaviorTree.CPP reads XML with tinyxml2).
pub const NESTING_MAX: usize = 500;

/// The longest element name, attribute name, and `ID` or `name` value: names
/// are shown on every screen and matched by the finder.
pub const NAME_MAX: usize = 4096;
/// The longest other attribute value (a port, a script) or text.
pub const ATTRIBUTE_MAX: usize = 1 << 20;

/// Parses a whole document and returns its top element.
pub fn parse_document(path: &Path, text: &str) -> Result<Element, Located> {
    let mut reader = Reader::from_str(text);
    reader.config_mut().trim_text(true);
    let mut stack: Vec<Element> = Vec::new();
    let mut top: Option<Element> = None;
    loop {
        let prev_end = reader.buffer_position() as usize;
        let event = match reader.read_event() {
            Ok(ev) => ev,
            Err(e) => {
                let pos = reader.error_position() as usize;
                let end = (pos + 1).min(text.len());
                return Err(Located::at(
                    path,
                    text,
                    pos,
                    end,
                    format!("malformed XML: {e}"),
                ));
            }
        };
        // With trimming, the whitespace before a tag belongs to no event.
        let start = prev_end + text[prev_end.min(text.len())..].find('<').unwrap_or(0);
        let end = reader.buffer_position() as usize;
        match event {
            Event::Start(e) => {
                if stack.len() >= NESTING_MAX {
                    return Err(Located::at(
                        path,
                        text,
                        start,
                        end,
                        format!("elements nest deeper than {NESTING_MAX} levels, which BehaviorTree.CPP's XML reader (tinyxml2) refuses too"),
                    ));
                }
                stack.push(element(path, text, &e, start, end)?);
            }
            Event::Empty(e) => {
                let el = element(path, text, &e, start, end)?;
                attach(path, text, &mut stack, &mut top, el)?;
            }
            Event::End(_) => {
                let el = stack.pop().expect("quick-xml checks end names");
                attach(path, text, &mut stack, &mut top, el)?;
            }
            Event::Eof => break,
            other => {
                if let Some(cur) = stack.last_mut() {
                    append_text(&mut cur.text, &other);
                }
            }
        }
    }
    finished(path, text, &stack, top)
}

/// Text, CDATA and character references inside an element, kept as its
/// text; comments, declarations and the like are not.
fn append_text(to: &mut String, event: &Event) {
    match event {
        Event::Text(t) => to.push_str(t),
        Event::CData(t) => to.push_str(t),
        Event::GeneralRef(r) => {
            if let Ok(Some(c)) = r.resolve_char_ref() {
                to.push(c);
            } else if let Some(s) = quick_xml::escape::resolve_predefined_entity(r) {
                to.push_str(s);
            }
        }
        _ => {}
    }
}

/// The document's top element once the reader is at its end: an error if
/// an element is left open or there is none.
fn finished(
    path: &Path,
    text: &str,
    stack: &[Element],
    top: Option<Element>,
) -> Result<Element, Located> {
    if let Some(open) = stack.last() {
        return Err(Located::at(
            path,
            text,
            open.start,
            open.end,
            format!("malformed XML: <{}> is never closed", open.tag),
        ));
    }
    top.ok_or_else(|| {
        Located::at(
            path,
            text,
            text.len(),
            text.len(),
            "malformed XML: the document has no element",
        )
    })
}

fn attach(
    path: &Path,
    text: &str,
    stack: &mut [Element],
    top: &mut Option<Element>,
    el: Element,
) -> Result<(), Located> {
    match stack.last_mut() {
        Some(parent) => parent.children.push(el),
        None if top.is_none() => *top = Some(el),
        None => {
            return Err(Located::at(
                path,
                text,
                el.start,
                el.end,
                "malformed XML: more than one top-level element",
            ))
        }
    }
    Ok(())
}

/// An attribute value as BehaviorTree.CPP's XML reader (tinyxml2,
/// `StrPair::GetStr` with entity processing) reads it: the five predefined
/// entities and character references are replaced, and an `&` that starts
/// none of them is literal text, so `code="a && b"` is the script `a && b`,
/// as BT.CPP's own tests and tutorials write it. Tabs and line breaks
/// become spaces (XML's attribute normalisation; scripts read them alike).
pub fn attr_value(raw: &str) -> String {
    let mut out = String::with_capacity(raw.len());
    let mut rest = raw;
    while let Some(c) = rest.chars().next() {
        if c == '&' {
            if let Some((r, len)) = reference(rest) {
                out.push(r);
                rest = &rest[len..];
                continue;
            }
        }
        if c == '\r' && rest[1..].starts_with('\n') {
            rest = &rest[1..];
            continue;
        }
        out.push(if matches!(c, '\t' | '\n' | '\r') {
            ' '
        } else {
            c
        });
        rest = &rest[c.len_utf8()..];
    }
    out
}

/// The reference `s` starts with (`&lt;`, `&#65;`, `&#x41;`) and its length.
fn reference(s: &str) -> Option<(char, usize)> {
    let end = s.get(1..12.min(s.len()))?.find(';')? + 1;
    let name = &s[1..end];
    let c = match name {
        "lt" => '<',
        "gt" => '>',
        "amp" => '&',
        "quot" => '"',
        "apos" => '\'',
        _ => {
            let code = match name.strip_prefix("#x") {
                Some(hex) => u32::from_str_radix(hex, 16).ok()?,
                None => name.strip_prefix('#')?.parse().ok()?,
            };
            char::from_u32(code).filter(|&c| c != '\0')?
        }
    };
    Some((c, end + 1))
}

fn element(
    path: &Path,
    text: &str,
    e: &BytesStart,
    start: usize,
    end: usize,
) -> Result<Element, Located> {
    let tag = e.name().0.to_string();
    let too_long = |what: &str, len: usize, max: usize| {
        Located::at(
            path,
            text,
            start,
            end,
            format!("{what} is {len} bytes long, more than the {max} bytes btx reads"),
        )
    };
    if tag.len() > NAME_MAX {
        return Err(too_long("the element name", tag.len(), NAME_MAX));
    }
    let mut attrs = Vec::new();
    for a in e.attributes() {
        let a = a.map_err(|err| {
            Located::at(
                path,
                text,
                start,
                end,
                format!("malformed XML attribute: {err}"),
            )
        })?;
        let value = attr_value(&a.value);
        let key = a.key.0.to_string();
        if key.len() > NAME_MAX {
            return Err(too_long("an attribute name", key.len(), NAME_MAX));
        }
        let max = if matches!(key.as_str(), "ID" | "name") {
            NAME_MAX
        } else {
            ATTRIBUTE_MAX
        };
        if value.len() > max {
            return Err(too_long(&format!("attribute {key}"), value.len(), max));
        }
        attrs.push(Attr { key, value });
    }
    Ok(Element {
        tag,
        attrs,
        children: Vec::new(),
        start,
        end,
        text: String::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ampersand_that_starts_no_entity_is_text_as_tinyxml2_reads_it() {
        assert_eq!(attr_value("a==1 && b==2"), "a==1 && b==2");
        assert_eq!(
            attr_value("a &lt; 3 &amp;&amp; b &gt; 1 &#x41;&#66;"),
            "a < 3 && b > 1 AB"
        );
        assert_eq!(
            attr_value("&quot;x&apos; &unknown; &#xZZ; &#0; &"),
            "\"x' &unknown; &#xZZ; &#0; &"
        );
        assert_eq!(attr_value("a\r\nb\tc\nd"), "a b c d");
        let src = "<root>\n  <S code=\"a && b\"/>\n</root>";
        let root = parse_document(Path::new("t.xml"), src).unwrap();
        assert_eq!(root.children[0].attr("code"), Some("a && b"));
    }

    #[test]
    fn keeps_spans_of_start_tags() {
        let src = "<root>\n  <A x=\"1\"/>\n  <B>\n  </B>\n</root>";
        let root = parse_document(Path::new("t.xml"), src).unwrap();
        assert_eq!(root.children.len(), 2);
        let a = &root.children[0];
        assert_eq!(&src[a.start..a.end], "<A x=\"1\"/>");
        assert_eq!(a.attr("x"), Some("1"));
        let b = &root.children[1];
        assert_eq!(&src[b.start..b.end], "<B>");
    }

    #[test]
    fn mismatched_tags_are_located() {
        let src = "<root>\n  <Sequence>\n  </Fallback>\n</root>";
        let e = parse_document(Path::new("bad.xml"), src).unwrap_err();
        assert!(
            e.to_string().starts_with("bad.xml:3:3: malformed XML"),
            "{e}"
        );
    }

    #[test]
    fn unclosed_element_is_located() {
        let src = "<root>\n  <Sequence>";
        let e = parse_document(Path::new("bad.xml"), src).unwrap_err();
        assert!(e.to_string().starts_with("bad.xml:"), "{e}");
        assert!(e.to_string().contains("malformed XML"), "{e}");
    }
}
