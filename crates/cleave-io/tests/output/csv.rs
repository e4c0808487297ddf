use super::common::scratch;
use cleave_io::output::{CsvWriter, Field};
use std::io::ErrorKind;

#[test]
fn header_and_rows_parse_back_bit_exactly() {
    let values = [
        0.0,
        -0.0,
        0.1,
        1.0 / 3.0,
        -2.5e-300,
        5e-324,
        f64::MAX,
        1e16,
        123456.789e3,
        -7.25e-6,
    ];
    let mut w = CsvWriter::new(Vec::new(), &["time", "node", "value", "note"]).unwrap();
    for (k, &x) in values.iter().enumerate() {
        w.row(&[
            Field::F(x),
            Field::I(k as i64 - 3),
            Field::F(-x),
            Field::Empty,
        ])
        .unwrap();
    }
    let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("time,node,value,note"));
    for (k, &x) in values.iter().enumerate() {
        let fields: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(fields.len(), 4);
        assert_eq!(fields[0].parse::<f64>().unwrap().to_bits(), x.to_bits());
        assert_eq!(fields[1].parse::<i64>().unwrap(), k as i64 - 3);
        assert_eq!(fields[2].parse::<f64>().unwrap().to_bits(), (-x).to_bits());
        assert_eq!(fields[3], "");
    }
    assert_eq!(lines.next(), None);
    assert!(text.ends_with('\n'));
}

#[test]
fn wrong_row_length_is_an_error() {
    let mut w = CsvWriter::new(Vec::new(), &["a", "b"]).unwrap();
    let short = w.row(&[Field::F(1.0)]).unwrap_err();
    assert_eq!(short.kind(), ErrorKind::InvalidInput);
    let long = w.row(&[Field::I(1), Field::I(2), Field::I(3)]).unwrap_err();
    assert_eq!(long.kind(), ErrorKind::InvalidInput);
    w.row(&[Field::I(1), Field::Empty]).unwrap();
    let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
    assert_eq!(text, "a,b\n1,\n", "rejected rows must not be written");
}

#[test]
fn bad_headers_are_errors() {
    assert!(CsvWriter::new(Vec::new(), &[]).is_err());
    assert!(CsvWriter::new(Vec::new(), &["a,b"]).is_err());
    assert!(CsvWriter::new(Vec::new(), &["a", ""]).is_err());
}

#[test]
fn non_finite_values_are_written_as_nan_and_inf() {
    let mut w = CsvWriter::new(Vec::new(), &["x", "y", "z"]).unwrap();
    w.row(&[
        Field::F(f64::NAN),
        Field::F(f64::INFINITY),
        Field::F(f64::NEG_INFINITY),
    ])
    .unwrap();
    let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
    assert_eq!(text, "x,y,z\nnan,inf,-inf\n");
}

#[test]
fn create_writes_a_file() {
    let path = scratch("csv_create").join("glstat.csv");
    let mut w = CsvWriter::create(&path, &["time", "dt"]).unwrap();
    w.row(&[Field::F(0.0), Field::F(1.25e-7)]).unwrap();
    w.row(&[2.5e-7.into(), None.into()]).unwrap();
    w.flush().unwrap();
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "time,dt\n0,1.25e-7\n2.5e-7,\n"
    );
}
