package lasonic.spy;

import java.awt.Graphics2D;
import java.awt.event.ActionEvent;
import java.awt.geom.Line2D;
import javax.swing.AbstractAction;
import javax.swing.Action;
import javax.swing.JDesktopPane;
import lasonic.line_map_t;
import lasonic.line_segment_t;
import lcm.spy.ChannelData;
import lcm.spy.SpyPlugin;

/**
 * lcm-spy plugin for {@code lasonic.line_map_t} (CURRENT_SENSOR_MAP, RADAR_MAP, AGM_LINES): line
 * segments in the odometry frame, centred on the robot, coloured by source: laser (Radar Map)
 * or sonar (lines generated from the tactical AGM).
 */
public class LineMapPlugin implements SpyPlugin {
  @Override public boolean canHandle(long fingerprint) {
    return fingerprint == line_map_t.LCM_FINGERPRINT;
  }

  @Override public Action getAction(final JDesktopPane desktop, final ChannelData cd) {
    return new AbstractAction("lasonic line map") {
      private static final long serialVersionUID = 1L;
      @Override public void actionPerformed(ActionEvent e) {
        if (desktop != null && cd != null) MapViewer.open(desktop, "Lines", cd, new Panel());
      }
    };
  }

  public static class Panel extends MapPanel {
    private static final long serialVersionUID = 1L;
    private line_map_t m;

    public Panel() {
      legend.add(new Object[] {Style.LASER, "laser line"});
      legend.add(new Object[] {Style.SONAR_LINE, "sonar line (tactical AGM)"});
    }

    @Override public void setMessage(Object msg) {
      if (!(msg instanceof line_map_t)) {
        m = null;
        status = "not a line_map_t: " + (msg == null ? "null" : msg.getClass().getName());
        return;
      }
      m = (line_map_t) msg;
      int laser = 0, sonar = 0, bad = 0;
      line_segment_t[] segs = m.segments == null ? new line_segment_t[0] : m.segments;
      for (line_segment_t s : segs) {
        if (s == null || !finite(s.x0, s.y0, s.x1, s.y1)) bad++;
        else if (s.source == line_segment_t.SOURCE_LASER) laser++;
        else if (s.source == line_segment_t.SOURCE_SONAR) sonar++;
        else bad++;
      }
      status = String.format("%d laser + %d sonar lines", laser, sonar) + (bad > 0 ? ", " + bad + " invalid skipped" : "");
    }

    @Override protected double[] centre() {
      if (m == null || m.robot_pose == null) return new double[] {0, 0};
      return new double[] {m.robot_pose.x, m.robot_pose.y};
    }

    @Override protected void paintWorld(Graphics2D g) {
      if (m == null || m.segments == null) return;
      g.setStroke(stroke(2.5));
      for (line_segment_t s : m.segments) {
        if (s == null || !finite(s.x0, s.y0, s.x1, s.y1)) continue;
        if (s.source == line_segment_t.SOURCE_LASER) g.setColor(Style.LASER);
        else if (s.source == line_segment_t.SOURCE_SONAR) g.setColor(Style.SONAR_LINE);
        else continue;
        g.draw(new Line2D.Double(s.x0, s.y0, s.x1, s.y1));
      }
      if (m.robot_pose != null) paintRobot(g, m.robot_pose.x, m.robot_pose.y, m.robot_pose.theta, Style.ROBOT_RADIUS);
    }
  }
}
