//! A document of regions: made from the boundary, split by interfaces,
//! its groups and regions named.

use crate::app::error::EditorError;
use crate::app::text::plural;
use crate::app::{regions, App};
use crate::geom::Point;

impl App {
    /// Makes the boundary a document of regions.
    pub(in crate::app) fn make_regions(&mut self) -> Result<String, EditorError> {
        self.edit("regions", |d| {
            d.to_regions()?;
            Ok("a document of regions: split it with the interface tool, name its groups and regions in the Regions panel".into())
        })
    }

    /// A curve from node `from` through `through` to node `to` becomes an
    /// interface.
    pub(in crate::app) fn split_region(
        &mut self,
        from: usize,
        through: Vec<Point>,
        to: usize,
    ) -> Result<String, EditorError> {
        self.graph_edit("interface", |g| {
            regions::with_interface(g, from, &through, to)
        })
    }

    /// Names the group of these segments.
    pub(in crate::app) fn name_group(
        &mut self,
        segments: Vec<usize>,
        name: String,
        tag: i64,
    ) -> Result<String, EditorError> {
        self.graph_edit("name group", |g| {
            regions::with_group(g, &segments, &name, tag)
        })
    }

    /// Names the region of the face holding `at`.
    pub(in crate::app) fn name_region(
        &mut self,
        at: Point,
        name: String,
        tag: i64,
    ) -> Result<String, EditorError> {
        self.graph_edit("name region", |g| regions::with_region(g, at, &name, tag))
    }

    /// An edit of a document of regions: the new graph from the current
    /// one, validated (an invalid graph is kept with its problem).
    pub(in crate::app) fn graph_edit(
        &mut self,
        what: &'static str,
        f: impl FnOnce(&crate::pslg::Pslg) -> Result<crate::pslg::Pslg, EditorError>,
    ) -> Result<String, EditorError> {
        let graph = match &self.document.doc.regions {
            Some(r) => f(&r.graph)?,
            None => {
                return Err(EditorError::RegionEdit(
                    "regions and groups are edited in a document of regions (open a file with several regions)".into(),
                ))
            }
        };
        self.edit(what, |d| {
            d.set_graph(graph)?;
            let r = d.regions.as_ref().ok_or(EditorError::NotFinished)?;
            Ok(match &r.problem {
                None => format!(
                    "{what}: {} in {}; mesh restarted",
                    plural(r.faces.len(), "face"),
                    plural(r.legend.len(), "region")
                ),
                Some(e) => format!("{what}: not a valid graph yet: {e}"),
            })
        })
    }
}
