//! Parquet files written and read a column at a time, through the parquet
//! crate's own column API (arrow would hold a second copy of each column).
//! The fleet's tables and the Parquet session file are both written here.

use crate::source::Located;
use parquet::data_type::{BoolType, ByteArray, ByteArrayType, DataType, Int32Type, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::reader::RowGroupReader;
use parquet::file::writer::{SerializedFileWriter, SerializedRowGroupWriter};
use parquet::schema::parser::parse_message_type;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn failed(path: &Path, e: impl std::fmt::Display) -> Located {
    Located::file(path, format!("cannot write the Parquet file: {e}"))
}

/// A Parquet file being written at `part`, a row group at a time; errors
/// name `path`, the file it becomes.
pub struct Writer {
    path: PathBuf,
    w: SerializedFileWriter<File>,
}

impl Writer {
    /// Creates `part` (it must not exist) for a file of `schema`.
    pub fn create(
        path: &Path,
        part: &Path,
        schema: &str,
        props: WriterProperties,
    ) -> Result<Writer, Located> {
        let schema = Arc::new(parse_message_type(schema).map_err(|e| failed(path, e))?);
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(part)
            .map_err(|e| failed(part, e))?;
        let w = SerializedFileWriter::new(file, schema, Arc::new(props))
            .map_err(|e| failed(path, e))?;
        Ok(Writer {
            path: path.to_path_buf(),
            w,
        })
    }

    /// One row group, its columns written by `columns` in the schema's order.
    pub fn row_group(
        &mut self,
        columns: impl FnOnce(&mut Columns) -> parquet::errors::Result<()>,
    ) -> Result<(), Located> {
        let mut rg = self.w.next_row_group().map_err(|e| failed(&self.path, e))?;
        columns(&mut Columns { rg: &mut rg }).map_err(|e| failed(&self.path, e))?;
        rg.close().map_err(|e| failed(&self.path, e))?;
        Ok(())
    }

    /// Writes the footer; the file is then whole, and synced to disk.
    pub fn close(self) -> Result<(), Located> {
        let path = self.path.clone();
        let file = self.close_unsynced()?;
        file.sync_all().map_err(|e| failed(&path, e))
    }

    /// Writes the footer, leaving the sync to the caller (an export of
    /// thousands of files syncs them all at once).
    pub fn close_unsynced(self) -> Result<File, Located> {
        let path = self.path;
        self.w.into_inner().map_err(|e| failed(&path, e))
    }
}

/// The next columns of a row group, by type.
pub struct Columns<'a, 'b> {
    rg: &'a mut SerializedRowGroupWriter<'b, File>,
}

impl Columns<'_, '_> {
    /// The next column, of Parquet type `P`; `None` is a missing value (the
    /// column is OPTIONAL).
    pub fn column<P: DataType>(
        &mut self,
        values: impl Iterator<Item = Option<P::T>>,
    ) -> parquet::errors::Result<()> {
        let (vals, defs) = split(values);
        let mut c = self.rg.next_column()?.expect("a column of the schema");
        let w = c.typed::<P>();
        let defs = (w.get_descriptor().max_def_level() > 0).then_some(defs);
        w.write_batch(&vals, defs.as_deref(), None)?;
        c.close()
    }

    /// A text column.
    pub fn strings<'s>(
        &mut self,
        values: impl Iterator<Item = Option<&'s str>>,
    ) -> parquet::errors::Result<()> {
        self.column::<ByteArrayType>(
            values.map(|v| v.map(|s| ByteArray::from(s.as_bytes().to_vec()))),
        )
    }

    /// A text column of few distinct values, each made once (`texts`) and
    /// shared by the rows that hold it (by index): a copy a row was most
    /// of an export's time.
    pub fn shared_strings(
        &mut self,
        texts: &[ByteArray],
        values: impl Iterator<Item = usize>,
    ) -> parquet::errors::Result<()> {
        self.column::<ByteArrayType>(values.map(|i| Some(texts[i].clone())))
    }

    pub fn ints(
        &mut self,
        values: impl Iterator<Item = Option<i32>>,
    ) -> parquet::errors::Result<()> {
        self.column::<Int32Type>(values)
    }

    pub fn longs(
        &mut self,
        values: impl Iterator<Item = Option<i64>>,
    ) -> parquet::errors::Result<()> {
        self.column::<Int64Type>(values)
    }

    pub fn bools(&mut self, values: impl Iterator<Item = bool>) -> parquet::errors::Result<()> {
        self.column::<BoolType>(values.map(Some))
    }
}

/// A column's values present, and the definition levels an OPTIONAL
/// column marks each row with (1 present, 0 missing).
fn split<T>(values: impl Iterator<Item = Option<T>>) -> (Vec<T>, Vec<i16>) {
    let n = values.size_hint().0;
    let mut vals = Vec::with_capacity(n);
    let mut defs = Vec::with_capacity(n);
    for v in values {
        defs.push(i16::from(v.is_some()));
        vals.extend(v);
    }
    (vals, defs)
}

/// Column `i` of a row group of `rows` rows, a value or `None` a row.
pub fn column<P: DataType>(
    rg: &dyn RowGroupReader,
    i: usize,
    rows: usize,
) -> parquet::errors::Result<Vec<Option<P::T>>> {
    let mut r = P::get_column_reader(rg.get_column_reader(i)?).ok_or_else(|| {
        parquet::errors::ParquetError::General(format!(
            "column {} is not of type {}",
            i + 1,
            P::get_physical_type()
        ))
    })?;
    let optional = rg.metadata().schema_descr().column(i).max_def_level() > 0;
    let (mut vals, mut defs) = (Vec::with_capacity(rows), Vec::with_capacity(rows));
    let mut read = 0;
    while read < rows {
        let (n, _, _) = r.read_records(rows - read, Some(&mut defs), None, &mut vals)?;
        if n == 0 {
            break;
        }
        read += n;
    }
    if read != rows || (optional && defs.len() != rows) {
        return Err(parquet::errors::ParquetError::General(format!(
            "column {} holds {read} of its row group's {rows} rows",
            i + 1
        )));
    }
    if !optional {
        return Ok(vals.into_iter().map(Some).collect());
    }
    let mut vals = vals.into_iter();
    defs.iter()
        .map(|&d| match d {
            0 => Ok(None),
            _ => vals.next().map(Some).ok_or_else(|| {
                parquet::errors::ParquetError::General(format!(
                    "column {} has fewer values than its levels say",
                    i + 1
                ))
            }),
        })
        .collect()
}
