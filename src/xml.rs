//! The one XML reader of every file format (hull, network, options, model description, and
//! the build script), with the one escape and the one number formatter used to write them.
//!
//! [`parse`] reads a whole document into an [`Element`] tree. It is strict: the text must be
//! well-formed with exactly one root element; the only entities are `&lt; &gt; &amp; &quot;
//! &apos;` and character references (`&#65;`, `&#x41;`); a DOCTYPE is refused, and so are
//! characters XML does not allow. Comments and processing instructions are skipped; the XML
//! declaration may only stand at the very start. Every error carries the 1-based line.
//!
//! The reader is iterative: open elements wait on an explicit stack, and dropping a tree walks
//! it with a work list, so no input can exhaust the call stack. Four limits ([`MAX_INPUT_BYTES`],
//! [`MAX_DEPTH`], [`MAX_ELEMENTS`], [`MAX_ATTRIBUTES`]) are checked before anything is allocated
//! for what would exceed them; the refusal names the limit and the line.
//!
//! This file depends only on `std` and `quick_xml`: the build script includes it as a module.

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::fmt;

/// Largest document read, in bytes (64 MiB): about a million elements of 40 to 60 bytes, as
/// many as [`MAX_ELEMENTS`] allows (a hull file of 10,000 contour points with 98 elastic
/// modes); anything larger is not a hull, network, options or model description file.
pub const MAX_INPUT_BYTES: usize = 64 * 1024 * 1024;

/// Deepest nesting of elements (the root is at depth 1). Our formats nest at most 4 deep
/// (`fmiModelDescription/ModelStructure/Outputs/Unknown`); 64 leaves room for vendor
/// annotations in model descriptions written by other tools.
pub const MAX_DEPTH: usize = 64;

/// Most elements in one document: a hull file of 10,000 contour points with 98 elastic modes
/// (990,000 point and mode-vector elements). Bounds the tree's memory to a few hundred MB.
pub const MAX_ELEMENTS: usize = 1_000_000;

/// Most attributes on one element. The richest element we read, `<CoSimulation>` of an FMI 2.0
/// model description, has 13; the check for repeated names costs the square of this number.
pub const MAX_ATTRIBUTES: usize = 256;

/// Why a document could not be read: the 1-based line and the problem.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct XmlError {
    /// 1-based line of the problem.
    pub line: usize,
    /// What is wrong, without the location.
    pub message: String,
}

impl XmlError {
    /// An error at `line`.
    pub fn new(line: usize, message: impl Into<String>) -> Self {
        XmlError {
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for XmlError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for XmlError {}

/// One element: its name, attributes (in document order, values unescaped), child elements,
/// the text directly inside it (unescaped, all pieces joined, whitespace kept) and its line.
/// Trees from [`parse`] are at most [`MAX_DEPTH`] deep; dropping one of any depth is iterative.
#[derive(Debug)]
pub struct Element {
    /// Element name as written (with any prefix).
    pub name: String,
    /// `(name, value)` pairs; names are unique.
    pub attributes: Vec<(String, String)>,
    /// Child elements in document order.
    pub children: Vec<Element>,
    /// Character data directly inside this element (not inside its children).
    pub text: String,
    /// 1-based line of the start tag's `<`.
    pub line: usize,
    /// 1-based line where the first non-whitespace character of `text` stands (`line` when
    /// there is none).
    pub text_line: usize,
}

impl Drop for Element {
    /// Iterative: a deep tree does not recurse once per level.
    fn drop(&mut self) {
        let mut pending = std::mem::take(&mut self.children);
        while let Some(mut element) = pending.pop() {
            pending.append(&mut element.children);
        }
    }
}

impl Element {
    /// An error located at this element's start tag.
    pub fn error(&self, message: impl Into<String>) -> XmlError {
        XmlError::new(self.line, message)
    }

    /// The value of attribute `key`, if present.
    pub fn attribute(&self, key: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The value of attribute `key`; missing is an error.
    pub fn required(&self, key: &str) -> Result<&str, XmlError> {
        self.attribute(key)
            .ok_or_else(|| self.error(format!("<{}> is missing the attribute {key}", self.name)))
    }

    /// Attribute `key` as a finite number; missing or not a finite number is an error.
    pub fn required_number(&self, key: &str) -> Result<f64, XmlError> {
        let text = self.required(key)?;
        self.attribute_number(key, text)
    }

    /// Attribute `key` as a finite number, `default` when it is absent.
    pub fn optional_number(&self, key: &str, default: f64) -> Result<f64, XmlError> {
        match self.attribute(key) {
            Some(text) => self.attribute_number(key, text),
            None => Ok(default),
        }
    }

    fn attribute_number(&self, key: &str, text: &str) -> Result<f64, XmlError> {
        parse_number(text)
            .map_err(|why| self.error(format!("{key}=\"{text}\" in <{}> {why}", self.name)))
    }

    /// Refuses any attribute not in `allowed` (for formats that allow no others).
    pub fn only_attributes(&self, allowed: &[&str]) -> Result<(), XmlError> {
        match self
            .attributes
            .iter()
            .find(|(k, _)| !allowed.contains(&k.as_str()))
        {
            Some((key, _)) => Err(self.error(format!(
                "unknown attribute {key} in <{}>; allowed: {}",
                self.name,
                if allowed.is_empty() {
                    "none".to_string()
                } else {
                    allowed.join(", ")
                }
            ))),
            None => Ok(()),
        }
    }

    /// Refuses child elements (the error is on the first child's line).
    pub fn no_children(&self) -> Result<(), XmlError> {
        match self.children.first() {
            Some(child) => Err(XmlError::new(
                child.line,
                format!("<{}> cannot contain <{}>", self.name, child.name),
            )),
            None => Ok(()),
        }
    }

    /// True when the text holds more than XML whitespace.
    pub fn has_text(&self) -> bool {
        !self.text.bytes().all(is_xml_whitespace)
    }

    /// Refuses text other than whitespace (the error is on the text's line).
    pub fn no_text(&self) -> Result<(), XmlError> {
        if self.has_text() {
            Err(XmlError::new(
                self.text_line,
                format!("unexpected text {:?} in <{}>", self.text.trim(), self.name),
            ))
        } else {
            Ok(())
        }
    }

    /// The text as whitespace-separated finite numbers.
    pub fn text_numbers(&self) -> Result<Vec<f64>, XmlError> {
        self.text
            .split_ascii_whitespace()
            .map(|word| {
                parse_number(word)
                    .map_err(|why| self.error(format!("\"{word}\" in <{}> {why}", self.name)))
            })
            .collect()
    }

    /// This element and all below it in document order (start tags), walked with a work list.
    pub fn descendants(&self) -> Descendants<'_> {
        Descendants {
            pending: vec![self],
        }
    }
}

/// Iterator of [`Element::descendants`].
pub struct Descendants<'a> {
    pending: Vec<&'a Element>,
}

impl<'a> Iterator for Descendants<'a> {
    type Item = &'a Element;

    fn next(&mut self) -> Option<&'a Element> {
        let element = self.pending.pop()?;
        self.pending.extend(element.children.iter().rev());
        Some(element)
    }
}

/// Why a text is no finite number ([`parse_number`]); its text completes "`x` ...".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NumberError {
    /// Not a number at all: "is not a number".
    NotANumber,
    /// A number, but infinite or NaN: "is not a finite number".
    NotFinite,
}

impl fmt::Display for NumberError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            NumberError::NotANumber => "is not a number",
            NumberError::NotFinite => "is not a finite number",
        })
    }
}

impl std::error::Error for NumberError {}

impl From<NumberError> for String {
    fn from(error: NumberError) -> String {
        error.to_string()
    }
}

/// A finite number (surrounding whitespace allowed); the error completes "`x` ...": "is not a
/// number" or "is not a finite number".
///
/// # Errors
/// [`NumberError`]: no number, or not a finite one.
pub fn parse_number(text: &str) -> Result<f64, NumberError> {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(NumberError::NotFinite),
        Err(_) => Err(NumberError::NotANumber),
    }
}

/// Text safe in attribute values (either quote) and in character data: `& < > " '` become
/// `&amp; &lt; &gt; &quot; &apos;`.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            _ => out.push(c),
        }
    }
    out
}

/// Inverse of [`escape`], also reading character references; any other entity, an `&` without
/// `;`, or a reference to a character XML does not allow is an error.
///
/// # Errors
/// [`UnescapeError`], naming the bad `&` and its byte offset.
pub(crate) fn unescape(raw: &str) -> Result<String, UnescapeError> {
    unescape_at(raw).map_err(|(offset, message)| UnescapeError { offset, message })
}

/// A text `unescape` refuses: where its bad `&` is, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct UnescapeError {
    /// Byte offset of the bad `&`.
    pub offset: usize,
    /// What is wrong with it.
    pub message: String,
}

impl fmt::Display for UnescapeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for UnescapeError {}

impl From<UnescapeError> for String {
    fn from(error: UnescapeError) -> String {
        error.message
    }
}

/// `unescape`, with the byte offset of a bad `&` in the error.
fn unescape_at(raw: &str) -> Result<String, (usize, String)> {
    let mut out = String::with_capacity(raw.len());
    let mut done = 0;
    while let Some(amp) = raw[done..].find('&').map(|k| done + k) {
        out.push_str(&raw[done..amp]);
        let semi = raw[amp..]
            .find(';')
            .map(|k| amp + k)
            .ok_or_else(|| (amp, format!("'&' without a closing ';' in \"{raw}\"")))?;
        let entity = &raw[amp + 1..semi];
        let c = match entity {
            "lt" => '<',
            "gt" => '>',
            "amp" => '&',
            "quot" => '"',
            "apos" => '\'',
            _ if entity.starts_with('#') => character_reference(entity).ok_or_else(|| {
                (
                    amp,
                    format!("&{entity}; in \"{raw}\" is not a character XML allows"),
                )
            })?,
            _ => {
                return Err((
                    amp,
                    format!(
                        "unknown entity &{entity}; in \"{raw}\" (only &lt; &gt; &amp; &quot; \
                         &apos; and character references like &#65; are allowed)"
                    ),
                ))
            }
        };
        out.push(c);
        done = semi + 1;
    }
    out.push_str(&raw[done..]);
    Ok(out)
}

/// `#65` or `#x41` to the character, if it is one XML allows.
fn character_reference(entity: &str) -> Option<char> {
    let code = if let Some(hex) = entity.strip_prefix("#x") {
        if hex.is_empty() || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        u32::from_str_radix(hex, 16).ok()?
    } else {
        let dec = entity.strip_prefix('#')?;
        if dec.is_empty() || !dec.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        dec.parse().ok()?
    };
    char::from_u32(code).filter(|&c| is_xml_char(c))
}

/// How [`format_number`] spells a number. Every notation gives the shortest text that reads
/// back to the same f64; they differ only in form, and each file format keeps its own so that
/// files stay byte for byte what they were.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Notation {
    /// Always a decimal point or an exponent, `1.0`, `0.25`, `1e-7`, `1e16` (Rust's `{:?}`);
    /// negative zero is written `0.0`. Hull files (their fingerprint hashes this text).
    Float,
    /// Plain digits for magnitudes in [1e-4, 1e9) and zero, `1`, `0.25`, `1025`, an exponent
    /// otherwise, `1e-7`, `1.5e17`. Network files.
    Plain,
    /// Always an exponent, `1e0`, `2.5e-1`, `6.524907740328788e2` (Rust's `{:e}`). Tables and
    /// JSON reports.
    Scientific,
}

/// The one number formatter for our XML and text files (see [`Notation`]).
pub fn format_number(x: f64, notation: Notation) -> String {
    match notation {
        Notation::Float => {
            let x = if x == 0.0 { 0.0 } else { x };
            format!("{x:?}")
        }
        Notation::Plain => {
            let a = x.abs();
            if a == 0.0 || (1e-4..1e9).contains(&a) {
                format!("{x}")
            } else {
                format!("{x:e}")
            }
        }
        Notation::Scientific => format!("{x:e}"),
    }
}

fn is_xml_whitespace(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r')
}

/// XML 1.0 `Char`: tab, line feed, carriage return, and U+0020 upwards without U+FFFE, U+FFFF
/// (surrogates cannot occur in a Rust `char`).
fn is_xml_char(c: char) -> bool {
    matches!(c, '\t' | '\n' | '\r') || (c >= ' ' && c != '\u{fffe}' && c != '\u{ffff}')
}

/// 1-based line of byte `pos`, counted from the start.
fn line_of(text: &str, pos: usize) -> usize {
    let end = pos.min(text.len());
    text.as_bytes()[..end]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// Line numbers of increasing positions, counting each byte once.
struct LineCounter<'a> {
    text: &'a [u8],
    pos: usize,
    line: usize,
}

impl LineCounter<'_> {
    fn line(&mut self, pos: usize) -> usize {
        let pos = pos.min(self.text.len());
        if pos < self.pos {
            self.pos = 0;
            self.line = 1;
        }
        self.line += self.text[self.pos..pos]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.pos = pos;
        self.line
    }
}

fn to_usize<T: TryInto<usize>>(x: T) -> usize {
    x.try_into().unwrap_or(usize::MAX)
}

/// Names and values as text: quick-xml up to 0.37 hands out bytes, later versions `str`.
fn utf8<B: AsRef<[u8]> + ?Sized>(raw: &B) -> Option<&str> {
    std::str::from_utf8(raw.as_ref()).ok()
}

/// Size and character checks on the whole input, before anything is allocated.
fn check_input(text: &str) -> Result<(), XmlError> {
    if text.len() > MAX_INPUT_BYTES {
        return Err(XmlError::new(
            line_of(text, MAX_INPUT_BYTES),
            format!(
                "the document has {} bytes, more than the limit MAX_INPUT_BYTES = {MAX_INPUT_BYTES} \
                 (reached on this line)",
                text.len()
            ),
        ));
    }
    if let Some((pos, c)) = text.char_indices().find(|&(_, c)| !is_xml_char(c)) {
        return Err(XmlError::new(
            line_of(text, pos),
            format!("character U+{:04X} is not allowed in XML", u32::from(c)),
        ));
    }
    Ok(())
}

fn make_element(tag: &BytesStart, line: usize) -> Result<Element, XmlError> {
    let err = |m: String| XmlError::new(line, m);
    let name = utf8(tag.name().as_ref())
        .ok_or_else(|| err("element name is not UTF-8".into()))?
        .to_string();
    if name.is_empty() {
        return Err(err("element without a name".into()));
    }
    let mut attributes = Vec::new();
    for attribute in tag.attributes() {
        if attributes.len() == MAX_ATTRIBUTES {
            return Err(err(format!(
                "<{name}> has more than MAX_ATTRIBUTES = {MAX_ATTRIBUTES} attributes"
            )));
        }
        let attribute = attribute.map_err(|e| err(format!("bad attribute in <{name}>: {e}")))?;
        let key = utf8(attribute.key.as_ref())
            .ok_or_else(|| err(format!("attribute name in <{name}> is not UTF-8")))?
            .to_string();
        let raw = utf8(&*attribute.value)
            .ok_or_else(|| err(format!("attribute {key} of <{name}> is not UTF-8")))?;
        if raw.contains('<') {
            return Err(err(format!("'<' in the value of {key} in <{name}>")));
        }
        let value = unescape(raw).map_err(|why| err(format!("{key} in <{name}>: {why}")))?;
        attributes.push((key, value));
    }
    Ok(Element {
        name,
        attributes,
        children: Vec::new(),
        text: String::new(),
        line,
        text_line: line,
    })
}

/// Adds character data to the innermost open element; `first` is the byte of its first
/// non-whitespace character, if any. Outside the root only whitespace is allowed.
fn add_text(
    open: &mut [Element],
    text: &str,
    first: Option<usize>,
    lines: &mut LineCounter,
) -> Result<(), XmlError> {
    match (open.last_mut(), first) {
        (Some(element), first) => {
            if let Some(at) = first.filter(|_| !element.has_text()) {
                element.text_line = lines.line(at);
            }
            element.text.push_str(text);
            Ok(())
        }
        (None, Some(at)) => Err(XmlError::new(
            lines.line(at),
            "text outside the root element",
        )),
        (None, None) => Ok(()),
    }
}

/// Byte of the first non-whitespace character of `raw`, which starts at byte `at`.
fn first_text(raw: &str, at: usize) -> Option<usize> {
    raw.bytes()
        .position(|b| !is_xml_whitespace(b))
        .map(|k| at + k)
}

/// Reads a whole document (a leading byte order mark is skipped). See the module docs.
pub fn parse(text: &str) -> Result<Element, XmlError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    check_input(text)?;
    let mut lines = LineCounter {
        text: text.as_bytes(),
        pos: 0,
        line: 1,
    };
    let mut reader = Reader::from_str(text);
    reader.config_mut().check_comments = true;
    let mut open: Vec<Element> = Vec::new();
    let mut root: Option<Element> = None;
    let mut elements = 0_usize;
    loop {
        let before = to_usize(reader.buffer_position()).min(text.len());
        let event = reader.read_event().map_err(|e| {
            let at = to_usize(reader.error_position()).min(text.len());
            XmlError::new(line_of(text, at), format!("malformed XML: {e}"))
        })?;
        let finished = match &event {
            Event::Start(tag) | Event::Empty(tag) => {
                let start = text.as_bytes()[before..]
                    .iter()
                    .position(|&b| b == b'<')
                    .map_or(before, |k| before + k);
                let line = lines.line(start);
                let name = || String::from_utf8_lossy(tag.name().as_ref()).into_owned();
                if open.is_empty() && root.is_some() {
                    return Err(XmlError::new(
                        line,
                        format!(
                            "second top-level element <{}>: a document has one root element",
                            name()
                        ),
                    ));
                }
                if open.len() == MAX_DEPTH {
                    return Err(XmlError::new(
                        line,
                        format!(
                            "<{}> is nested deeper than the limit MAX_DEPTH = {MAX_DEPTH}",
                            name()
                        ),
                    ));
                }
                if elements == MAX_ELEMENTS {
                    return Err(XmlError::new(
                        line,
                        format!(
                            "<{}> is one element more than the limit MAX_ELEMENTS = \
                             {MAX_ELEMENTS}",
                            name()
                        ),
                    ));
                }
                elements += 1;
                let element = make_element(tag, line)?;
                if matches!(event, Event::Start(_)) {
                    open.push(element);
                    None
                } else {
                    Some(element)
                }
            }
            Event::End(_) => open.pop(),
            Event::Text(raw) => {
                let raw = utf8(&**raw)
                    .ok_or_else(|| XmlError::new(lines.line(before), "text is not UTF-8"))?;
                let value = unescape_at(raw)
                    .map_err(|(at, why)| XmlError::new(lines.line(before + at), why))?;
                add_text(&mut open, &value, first_text(raw, before), &mut lines)?;
                None
            }
            Event::CData(raw) => {
                let line = lines.line(before);
                let raw = utf8(&**raw).ok_or_else(|| XmlError::new(line, "text is not UTF-8"))?;
                if open.is_empty() {
                    return Err(XmlError::new(line, "CDATA outside the root element"));
                }
                let content = before + "<![CDATA[".len();
                add_text(&mut open, raw, first_text(raw, content), &mut lines)?;
                None
            }
            Event::Decl(_) if before > 0 => {
                return Err(XmlError::new(
                    lines.line(before),
                    "the XML declaration <?xml ...?> may only stand at the very start",
                ))
            }
            Event::DocType(_) => {
                return Err(XmlError::new(
                    lines.line(before),
                    "DOCTYPE is not allowed (no DTD; the only entities are &lt; &gt; &amp; \
                     &quot; &apos; and character references)",
                ))
            }
            Event::Decl(_) | Event::Comment(_) | Event::PI(_) => None,
            Event::Eof => break,
        };
        if let Some(element) = finished {
            match open.last_mut() {
                Some(parent) => parent.children.push(element),
                None => root = Some(element),
            }
        }
    }
    if let Some(element) = open.last() {
        return Err(element.error(format!("element <{}> is not closed", element.name)));
    }
    root.ok_or_else(|| XmlError::new(line_of(text, text.len()), "no root element"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str) -> XmlError {
        parse(text).expect_err("should be refused")
    }

    #[test]
    fn reads_elements_attributes_text_and_lines() {
        let text = "<?xml version=\"1.0\"?>\n<!-- c -->\n<a x=\"1 &amp; 2\" y='&#x41;&#66;'>\n  \
                    <b/> some &lt;text&gt;\n  <c><![CDATA[<raw>]]></c>\n</a>\n";
        let root = parse(text).unwrap();
        assert_eq!(root.name, "a");
        assert_eq!(root.line, 3);
        assert_eq!(root.attribute("x"), Some("1 & 2"));
        assert_eq!(root.attribute("y"), Some("AB"));
        assert_eq!(root.children.len(), 2);
        assert_eq!(root.children[0].line, 4);
        assert_eq!(root.children[1].text, "<raw>");
        assert_eq!(root.children[1].line, 5);
        assert!(root.has_text());
        assert_eq!(root.text_line, 4);
        assert_eq!(root.text.trim(), "some <text>");
        let names: Vec<&str> = root.descendants().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["a", "b", "c"]);
        // A byte order mark is skipped.
        assert_eq!(parse("\u{feff}<r/>").unwrap().name, "r");
    }

    #[test]
    fn typed_attributes_name_the_element_and_line() {
        let root = parse("<r>\n<p x=\"1.5\" y=\"nan\" z=\"one\" w=\"\"/>\n</r>").unwrap();
        let p = &root.children[0];
        assert_eq!(p.required_number("x"), Ok(1.5));
        assert_eq!(p.optional_number("q", 7.0), Ok(7.0));
        let e = p.required_number("y").unwrap_err();
        assert_eq!(e.line, 2);
        assert_eq!(e.message, "y=\"nan\" in <p> is not a finite number");
        assert!(p
            .required_number("z")
            .unwrap_err()
            .message
            .ends_with("is not a number"));
        assert!(p
            .required_number("w")
            .unwrap_err()
            .message
            .ends_with("is not a number"));
        let e = p.required("v").unwrap_err();
        assert_eq!(e.message, "<p> is missing the attribute v");
        let e = p.only_attributes(&["x", "y", "z"]).unwrap_err();
        assert_eq!(e.message, "unknown attribute w in <p>; allowed: x, y, z");
        assert!(p.only_attributes(&["x", "y", "z", "w"]).is_ok());
        assert!(root
            .no_children()
            .unwrap_err()
            .message
            .contains("<r> cannot contain <p>"));
        let row = parse("<row>\n 1 2.5\n -3e2 </row>").unwrap();
        assert_eq!(row.text_numbers(), Ok(vec![1.0, 2.5, -300.0]));
        assert_eq!(row.text_line, 2);
        let e = row.no_text().unwrap_err();
        assert_eq!(e.line, 2);
        let bad = parse("<row>1 x</row>").unwrap();
        assert_eq!(
            bad.text_numbers().unwrap_err().message,
            "\"x\" in <row> is not a number"
        );
    }

    #[test]
    fn malformed_inputs_give_line_numbers() {
        for (text, line, words) in [
            ("<a>\n<b>\n</c>\n</a>", 3, "malformed XML"),
            ("<a>\n<b>\n</a>", 3, "malformed XML"),
            ("<a>\n<b>", 2, "element <b> is not closed"),
            ("<a/>\n<b/>", 2, "second top-level element <b>"),
            ("", 1, "no root element"),
            ("\n\n", 3, "no root element"),
            ("<a/>\ntext", 2, "text outside the root element"),
            ("<a>\n&foo;</a>", 2, "unknown entity &foo;"),
            (
                "<a>\n&#0;</a>",
                2,
                "&#0; in \"\n&#0;\" is not a character XML allows",
            ),
            ("<a>\n&#x+41;</a>", 2, "is not a character"),
            ("<a>\n a & b</a>", 2, "'&' without a closing ';'"),
            ("<a\n x=\"&bar;\"/>", 1, "x in <a>: unknown entity &bar;"),
            ("<a x=\"1\" x=\"2\"/>", 1, "bad attribute in <a>"),
            ("<a x=1/>", 1, "bad attribute in <a>"),
            ("<a x=\"<\"/>", 1, "'<' in the value of x"),
            (
                "<!DOCTYPE a [<!ENTITY e \"x\">]>\n<a>&e;</a>",
                1,
                "DOCTYPE is not allowed",
            ),
            ("<a/>\n<?xml version=\"1.0\"?>", 2, "at the very start"),
            ("<a>\n<!-- a -- b -->\n</a>", 2, "malformed XML"),
            ("<a>\n\u{1}</a>", 2, "U+0001"),
            ("<a>\n<b x=\"1\"", 2, "malformed XML"),
        ] {
            let e = error(text);
            assert_eq!(e.line, line, "{text:?}: {e}");
            assert!(e.message.contains(words), "{text:?}: '{e}' lacks '{words}'");
        }
        assert_eq!(
            error("<a>\n<b>").to_string(),
            "line 2: element <b> is not closed"
        );
    }

    /// `<a>` nested `levels` deep, closed again.
    fn nested(levels: usize) -> String {
        let mut text = "<a>".repeat(levels);
        text.push_str(&"</a>".repeat(levels));
        text
    }

    fn check_deep_nesting() {
        let e = error(&nested(1_000_000));
        assert!(e.message.contains("MAX_DEPTH = 64"), "{e}");
        assert_eq!(e.line, 1);
        let mut text = "<a>\n".repeat(MAX_DEPTH + 1);
        text.push_str(&"</a>".repeat(MAX_DEPTH + 1));
        assert_eq!(error(&text).line, MAX_DEPTH + 1);
        assert!(parse(&nested(MAX_DEPTH)).is_ok());
        // Dropping a tree far deeper than the reader allows does not recurse.
        let leaf = || Element {
            name: "a".into(),
            attributes: Vec::new(),
            children: Vec::new(),
            text: String::new(),
            line: 1,
            text_line: 1,
        };
        let mut deep = leaf();
        for _ in 0..1_000_000 {
            let mut parent = leaf();
            parent.children.push(deep);
            deep = parent;
        }
        assert_eq!(deep.descendants().count(), 1_000_001);
        drop(deep);
    }

    #[test]
    fn deep_nesting_is_refused_without_exhausting_the_stack() {
        check_deep_nesting();
        std::thread::Builder::new()
            .stack_size(256 * 1024)
            .spawn(check_deep_nesting)
            .unwrap()
            .join()
            .unwrap();
    }

    #[test]
    fn too_many_elements_or_attributes_are_refused() {
        let mut text = String::from("<r>\n");
        text.push_str(&"<e/>".repeat(MAX_ELEMENTS - 1));
        text.push_str("\n</r>");
        assert_eq!(parse(&text).unwrap().children.len(), MAX_ELEMENTS - 1);
        let text = text.replace("\n</r>", "\n<e/></r>");
        let e = error(&text);
        assert_eq!(e.line, 3);
        assert!(e.message.contains("MAX_ELEMENTS = 1000000"), "{e}");

        let attributes = |n: usize| {
            let list: String = (0..n).map(|i| format!(" a{i}=\"{i}\"")).collect();
            format!("<r>\n<e{list}/></r>")
        };
        assert!(parse(&attributes(MAX_ATTRIBUTES)).is_ok());
        let e = error(&attributes(MAX_ATTRIBUTES + 1));
        assert_eq!(e.line, 2);
        assert!(e.message.contains("MAX_ATTRIBUTES = 256"), "{e}");
    }

    #[test]
    fn oversized_input_is_refused_with_the_line_of_the_limit() {
        let mut text = String::from("<r>\n");
        text.push_str(&" ".repeat(MAX_INPUT_BYTES));
        text.push_str("</r>");
        let e = error(&text);
        assert_eq!(e.line, 2);
        assert!(e.message.contains("MAX_INPUT_BYTES"), "{e}");
    }

    #[test]
    fn escape_and_unescape_round_trip() {
        for text in [
            "",
            "plain",
            "a&b<c>\"d\"'e'",
            "&amp; literally",
            "ünïcode ✓",
            "&&;;",
        ] {
            let escaped = escape(text);
            assert!(!escaped.contains(['<', '>', '"', '\'']), "{escaped}");
            assert_eq!(unescape(&escaped).as_deref(), Ok(text));
            let root = parse(&format!("<r v=\"{escaped}\" w='{escaped}'>{escaped}</r>")).unwrap();
            assert_eq!(root.attribute("v"), Some(text));
            assert_eq!(root.attribute("w"), Some(text));
            assert_eq!(root.text, text);
        }
        assert_eq!(escape("a&b<c>\"'"), "a&amp;b&lt;c&gt;&quot;&apos;");
        assert_eq!(
            unescape("&#65;&#x42;&#x1F600;").as_deref(),
            Ok("AB\u{1F600}")
        );
        assert!(unescape("&#xD800;").is_err());
        assert!(unescape("&#xFFFE;").is_err());
        assert!(unescape("&#;").is_err());
    }

    #[test]
    fn notations_read_back_exactly() {
        let cases = [
            (1.0, "1.0", "1", "1e0"),
            (0.0, "0.0", "0", "0e0"),
            (-0.0, "0.0", "-0", "-0e0"),
            (1025.0, "1025.0", "1025", "1.025e3"),
            (0.25, "0.25", "0.25", "2.5e-1"),
            (1e-4, "0.0001", "0.0001", "1e-4"),
            (1e-5, "1e-5", "1e-5", "1e-5"),
            (
                1.1124201786327026e-7,
                "1.1124201786327026e-7",
                "1.1124201786327026e-7",
                "1.1124201786327026e-7",
            ),
            (1e9, "1000000000.0", "1e9", "1e9"),
            (
                1.5208184907274435e17,
                "1.5208184907274435e17",
                "1.5208184907274435e17",
                "1.5208184907274435e17",
            ),
            (
                -2.126192793053796e-13,
                "-2.126192793053796e-13",
                "-2.126192793053796e-13",
                "-2.126192793053796e-13",
            ),
        ];
        for (x, float, plain, scientific) in cases {
            assert_eq!(format_number(x, Notation::Float), float);
            assert_eq!(format_number(x, Notation::Plain), plain);
            assert_eq!(format_number(x, Notation::Scientific), scientific);
        }
        let mut x = 1.234_567_890_123_456_7e-300;
        while x < 1e300 {
            for notation in [Notation::Float, Notation::Plain, Notation::Scientific] {
                for value in [x, -x, x * (1.0 + f64::EPSILON)] {
                    let text = format_number(value, notation);
                    assert_eq!(text.parse::<f64>(), Ok(value), "{text}");
                }
            }
            x *= 7.3;
        }
    }
}
