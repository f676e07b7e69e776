package lasonic.spy;

import java.awt.BasicStroke;
import java.awt.Color;
import java.awt.Graphics2D;
import java.awt.event.ActionEvent;
import java.awt.geom.Ellipse2D;
import java.awt.geom.Path2D;
import javax.swing.AbstractAction;
import javax.swing.Action;
import javax.swing.JDesktopPane;
import lasonic.sector_map_t;
import lcm.spy.ChannelData;
import lcm.spy.SpyPlugin;

/**
 * lcm-spy plugin for {@code lasonic.sector_map_t} (SECTOR_MAP): the pilot's polar world model,
 * drawn in the robot frame with straight ahead up. Each sector is filled from the robot's
 * boundary to its distance, coloured by where the value came from (laser, sonar, sonar copied
 * into a neighbour); stale sensors are flagged in red; the dashed circle is the map's reach.
 */
public class SectorMapPlugin implements SpyPlugin {
  @Override public boolean canHandle(long fingerprint) {
    return fingerprint == sector_map_t.LCM_FINGERPRINT;
  }

  @Override public Action getAction(final JDesktopPane desktop, final ChannelData cd) {
    // lcm-spy calls this with (null, null) just to read the action's name.
    return new AbstractAction("lasonic Sector Map") {
      private static final long serialVersionUID = 1L;
      @Override public void actionPerformed(ActionEvent e) {
        if (desktop != null && cd != null) MapViewer.open(desktop, "Sector Map", cd, new Panel());
      }
    };
  }

  /** The drawing, usable on its own (tests paint it into an image). */
  public static class Panel extends MapPanel {
    private static final long serialVersionUID = 1L;
    private sector_map_t m;

    public Panel() {
      scale = 80;
      legend.add(new Object[] {Style.alpha(Style.LASER, 140), "laser"});
      legend.add(new Object[] {Style.alpha(Style.SONAR, 190), "sonar"});
      legend.add(new Object[] {Style.alpha(Style.SONAR_COPIED, 220), "sonar, copied"});
    }

    @Override public void setMessage(Object msg) {
      flags.clear();
      if (!(msg instanceof sector_map_t)) {
        m = null;
        status = "not a sector_map_t: " + (msg == null ? "null" : msg.getClass().getName());
        return;
      }
      m = (sector_map_t) msg;
      int n = m.nsectors;
      if (n <= 0 || n > 3600 || m.distance == null || m.source == null || m.distance.length < n || m.source.length < n) {
        status = "invalid sector_map_t: nsectors " + n;
        m = null;
        return;
      }
      int[] count = new int[4];
      for (int k = 0; k < n; k++)
        if (m.source[k] >= 0 && m.source[k] < 4) count[m.source[k]]++;
      status = String.format("%d sectors: %d laser, %d sonar, %d copied, %d none", n, count[1], count[2], count[3], count[0]);
      flag("laser", m.laser_stale, m.laser_age_s);
      flag("sonar", m.sonar_stale, m.sonar_age_s);
    }

    private void flag(String sensor, byte stale, float age) {
      if (age < 0) flags.add(sensor + ": no data yet");
      else if (stale != 0) flags.add(sensor + " STALE: newest data " + String.format("%.2f s", age) + " old, values held");
    }

    @Override protected double[] centre() { return new double[] {0, 0}; }

    @Override protected void paintWorld(Graphics2D g) {
      if (m == null) return;
      // Robot frame, straight ahead up: bearing 0 (robot x) is drawn along +y.
      g.rotate(Math.PI / 2);
      double r = finite(m.robot_radius) && m.robot_radius > 0 && m.robot_radius < 10 ? m.robot_radius : 0.35;
      if (finite(m.max_range) && m.max_range > 0 && m.max_range < 100) {
        double R = r + m.max_range;
        g.setColor(Style.NOTE);
        g.setStroke(new BasicStroke((float) (1 / scale), BasicStroke.CAP_BUTT, BasicStroke.JOIN_MITER, 10,
                                    new float[] {(float) (4 / scale), (float) (4 / scale)}, 0));
        g.draw(new Ellipse2D.Double(-R, -R, 2 * R, 2 * R));
      }
      int n = m.nsectors;
      double w = 2 * Math.PI / n;
      for (int k = 0; k < n; k++) {
        double d = m.distance[k];
        if (!finite(d) || d < 0 || d > 100) continue;
        Color c;
        switch (m.source[k]) {
          case sector_map_t.SOURCE_LASER: c = Style.alpha(Style.LASER, 140); break;
          case sector_map_t.SOURCE_SONAR: c = Style.alpha(Style.SONAR, 190); break;
          case sector_map_t.SOURCE_SONAR_COPIED: c = Style.alpha(Style.SONAR_COPIED, 220); break;
          default: c = Style.alpha(Style.UNKNOWN, 120); break;
        }
        double a0 = -Math.PI + k * w;
        Path2D p = annulusSector(0, 0, r, r + d, a0, a0 + w);
        g.setColor(c);
        g.fill(p);
        g.setColor(Style.alpha(Style.TEXT, 90));
        g.setStroke(stroke(0.6));
        g.draw(p);
      }
      paintRobot(g, 0, 0, 0, r);
    }
  }
}
