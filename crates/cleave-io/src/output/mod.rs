//! Result writers: CSV histories, summary JSON, ParaView VTU/VTP/PVD, PNG plots.
