#include "evaluation/report/report_protocol.h"

namespace mavloc {

ReportProtocol ReportProtocolOf(const EvaluationProtocol& p, bool by_index) {
  ReportProtocol protocol;
  protocol.alignment = p.align_origin ? "origin" : AlignmentModeName(p.alignment);
  protocol.association = by_index                                     ? "index"
                         : p.association == AssociationMode::kNearest ? "nearest"
                                                                      : "interpolate";
  protocol.max_dt_s = p.max_dt_s;
  protocol.time_offset_s = p.time_offset_s;
  protocol.pose_relation = PoseRelationName(p.ape_relation);
  return protocol;
}

}  // namespace mavloc
